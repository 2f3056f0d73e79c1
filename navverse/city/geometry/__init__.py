"""A city map in 3-D: the ground plan, the ground at its heights, buildings, the scene.

:mod:`.surfaces` tiles the window with disjoint polygons per surface class (overlaps settled by one
priority order), :mod:`.crossings` adds crosswalks on junction arms, :mod:`.street_plan` is the plan
the scene is built from (saved as ``street_plan.json``), :mod:`.prisms` turns polygons into prisms,
:mod:`.ground` sets the ground at its heights (roads below curbs, crosswalk ramps), :mod:`.terrain`
gives it relief (seeded hills, or a GeoTIFF DEM read by :mod:`.dem`, graded so roads keep their
class's grade) and :mod:`.draped` lays ground pieces over it, :mod:`.buildings` extrudes the
buildings with their facades, :mod:`.scene` (:func:`.scene.city_scene`, with the
:class:`.scene.CityGeometry` settings) assembles the scene, and :mod:`.grades` measures the steepest
road grade per class in a built one.

Imports: the top-level city modules and :mod:`navverse.scene`; never OSM reading, synthetic
generation, street life, places or i2o. The package imports nothing itself.
"""
