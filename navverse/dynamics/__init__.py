"""Things that move in a scene besides the robot: pedestrians on the navmesh (:mod:`.crowd`,
:mod:`.pedestrians`) and cars on the lanes of the street plan (:mod:`.traffic`).

Its ``__init__`` imports nothing, so a module that needs one part loads only that part.
"""
