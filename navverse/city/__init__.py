"""Outdoor cities: the city map contract (:mod:`.map`) and OpenStreetMap tags read as numbers and
rules (:mod:`.tags`)."""
