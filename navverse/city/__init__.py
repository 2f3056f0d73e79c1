"""Outdoor cities: OpenStreetMap tags read as numbers and rules (:mod:`.tags`)."""
