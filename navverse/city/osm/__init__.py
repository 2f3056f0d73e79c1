"""City maps read from local OpenStreetMap files, and city maps written as OSM XML.

:func:`.reader.read_osm` reads a window of a ``.osm``, ``.osm.gz`` or ``.osm.pbf`` file
(:func:`.reader.check_window` checks one cheaply): file checks before parsing (:mod:`.files`), the
local UTM window (:mod:`.window`), the osmium stream that keeps the window's objects (:mod:`.stream`),
rings and clipping (:mod:`.geometry`) and the features built from them (:mod:`.features`).
:mod:`.writer` writes a city map as OSM XML that osmnx and JOSM read.

Imports: the top-level city modules (the map contract, tags, tag tables, clipping) and nothing else
of :mod:`navverse.city`. The package imports nothing itself.
"""
