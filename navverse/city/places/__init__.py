"""Places: storefronts set into a city's facades at the map's places.

:func:`.storefronts.place_storefronts` puts a procedural storefront (:mod:`navverse.assets.facade`)
on the nearest road-facing facade of every place with a place category, carves its recess and checks
its door and sign (:class:`.storefronts.StorefrontSettings`).

Imports: the top-level city modules, :mod:`navverse.city.geometry`, the synthetic cities' place
table (:mod:`navverse.city.synthetic.pois`), the object library and :mod:`navverse.scene`; never
i2o. The package imports nothing itself.
"""
