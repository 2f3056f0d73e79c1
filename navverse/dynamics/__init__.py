"""Things that move in a scene besides the robot: pedestrians on the navmesh (:mod:`.crowd`).

Its ``__init__`` imports nothing, so a module that needs one part loads only that part.
"""
