"""Outdoor cities: the city map contract (:mod:`.map`), OpenStreetMap tags read as numbers and rules
(:mod:`.tags`), and the 2-D ground plan of surface classes (:mod:`.surfaces`)."""
