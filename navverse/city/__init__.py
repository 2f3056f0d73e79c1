"""Outdoor cities: the city map contract (:mod:`.map`), OpenStreetMap tags read as numbers and rules
(:mod:`.tags`), the 2-D ground plan of surface classes (:mod:`.surfaces`), and synthetic grid cities
(:mod:`.synthetic`)."""
