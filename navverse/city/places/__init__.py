"""Places: storefronts set into a city's facades at the map's places.

:func:`.storefronts.place_storefronts` puts a procedural storefront (:mod:`navverse.assets.facade`)
on the nearest facade onto a street (a road, a pedestrian street or square) of every place with a
place category, or of a building near it, carves its recess and checks its door and sign
(:class:`.storefronts.StorefrontSettings`).

Imports: the top-level city modules, :mod:`navverse.city.geometry`, the synthetic cities' place
table (:mod:`navverse.city.synthetic.pois`), the object library and :mod:`navverse.scene`; never
i2o. The package imports nothing itself.
"""
