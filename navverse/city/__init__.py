"""Outdoor cities: the city map contract (:mod:`.map`), OpenStreetMap tags read as numbers and rules
(:mod:`.tags`), the 2-D ground plan of surface classes (:mod:`.surfaces`), synthetic grid cities
(:mod:`.synthetic`), and city maps written as OSM XML (:mod:`.osm_xml`)."""
