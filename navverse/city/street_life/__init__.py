"""Street life: what stands in a city's streets.

:mod:`.zones` lays the sidewalk zones and parking bands, :mod:`.objects` plans the mapped furniture
and the zone grammar's street objects, :mod:`.parking` the parking slots, :mod:`.group_catalogue`
holds the 30 contextual groups and :mod:`.groups` places them, :mod:`.populate` stands them all in a
city scene (:func:`.populate.populate_city`, with the :class:`.populate.PopulateSettings`), and
:mod:`.passability` compares the bare and populated navmeshes' sidewalk islands.

Imports: the top-level city modules, :mod:`navverse.city.geometry`, the object library and
:mod:`navverse.scene`; never places or i2o. The package imports nothing itself.
"""
