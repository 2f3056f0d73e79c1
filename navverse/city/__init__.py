"""Outdoor cities: the city map contract (:mod:`.map`), OpenStreetMap tags read as numbers and rules
(:mod:`.tags`), city maps read from local OSM files (:func:`.osm.read_osm`, with file checks in
:mod:`.osm_files`, the window in :mod:`.osm_window`, streaming in :mod:`.osm_read`, tag tables in
:mod:`.osm_classes`, geometry in :mod:`.osm_geometry` and the features in :mod:`.osm_features`), the
2-D ground plan of surface classes (:mod:`.surfaces`), synthetic cities (:mod:`.synthetic` and the
``synthetic_*`` modules), and city maps written as OSM XML (:mod:`.osm_xml`)."""
