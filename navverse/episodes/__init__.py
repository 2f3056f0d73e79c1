"""Building episodes: sampling on the navmesh, physics verification, VLN instructions, packaging."""
