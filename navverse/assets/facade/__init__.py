"""What is set into a building facade: procedural storefronts and the images of their sign boards.

:mod:`.storefronts` builds a storefront of a place category (its own categories, mapped from OSM
``amenity``/``shop`` tags, not categories of the registry) and :mod:`.storefront_signs` draws the
sign image it is textured with.

Imports: these modules import the core of :mod:`navverse.assets` (``parts``, ``primitives``,
``materials``, ``errors``), and ``storefronts`` imports ``storefront_signs``; nothing here imports an
object family or the registry :mod:`navverse.assets.library`, and no family imports this package.
This package imports nothing itself.
"""
