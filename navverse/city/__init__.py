"""Outdoor cities, in subpackages by what they are about.

At the top: the city map contract every producer writes and every consumer reads (:mod:`.map`),
OpenStreetMap tags read as numbers and rules (:mod:`.tags`) and the tag tables of places and land
(:mod:`.tag_tables`), the settings a city scene was built with (:mod:`.city_settings`), and two
helpers the subpackages share: a growing grid index of shapes (:mod:`.shape_grid`) and segment
clipping (:mod:`.clipping`).

- :mod:`.osm`: city maps read from local OSM files, and maps written as OSM XML.
- :mod:`.synthetic`: city maps drawn from a seed, with the records of a real one.
- :mod:`.geometry`: the map in 3-D: the ground plan of surface classes, crosswalks, the ground at
  its heights (roads below curbs), buildings with facades, the scene and its saved street plan.
- :mod:`.street_life`: what stands in a street: sidewalk zones, street objects, parked cars,
  contextual groups, the populated scene and its passability.
- :mod:`.places`: storefronts set into facades at the map's places.
- :mod:`.i2o`: an indoor building joined to a city through a facade, and its neighbourhood made
  busier.

Imports (checked by the import-linter contracts of ``pyproject.toml``): :mod:`.i2o` over
:mod:`.places` over :mod:`.street_life` over :mod:`.geometry`, none importing a package above it;
:mod:`.osm` imports none of the others; :mod:`.synthetic` imports neither :mod:`.osm` nor what
builds on the geometry (street life, places, i2o). Every subpackage may import the top-level
modules, which import no subpackage but :mod:`.city_settings` (the settings of geometry, street
life and places).
"""
