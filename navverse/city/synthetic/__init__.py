"""Synthetic cities: a seed and parameters give the same city map, with the records of a real one.

:func:`.generator.synthetic_city` draws the street network (:mod:`.streets`: grid, radial or
organic pieces sharing junction points; :mod:`.roads`: the roads' classes, widths and names), the
river and its bridges, the blocks (:mod:`.blocks`) and their land (:mod:`.land`: parks with ponds,
plazas, parking, buildings along block edges), ground-floor places (:mod:`.pois`, named by
:mod:`.names`) and furniture on the sidewalks (:mod:`.furniture`), within the knobs of
:mod:`.params`.

Imports: the top-level city modules (map contract, tags, tag tables, clipping) and the surface
widths of :mod:`navverse.city.geometry.surfaces`; never :mod:`navverse.city.osm`, street life,
places or i2o. The package imports nothing itself.
"""
