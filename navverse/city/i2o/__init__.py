"""Indoor-to-outdoor scenes: an indoor building joined to a city through a door in a road-facing facade.

:mod:`.assembly` sets the building's exit into the best facade (or generates a building sized to a
city building) and cuts the city to fit; :mod:`.densify` makes the neighbourhood of the exit busier
with storefronts, street objects and parked cars, by the city's own settings.

Imports: everything of :mod:`navverse.city` it builds on (geometry, street life, places), the
indoor generator and :mod:`navverse.scene`. The package imports nothing itself.
"""
