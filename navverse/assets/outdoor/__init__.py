"""Outdoor object families: what stands on streets, in parks, plazas and parking lots, on construction
sites and sports grounds, and what people carry and set down there.

One module per group of categories, each declaring ``ASSETS`` (a tuple of
:class:`~navverse.assets.spec.Asset` whose contexts are outdoor ones): :mod:`.vehicles`,
:mod:`.street_furniture` (poles, signals, boxes and shelters), :mod:`.street_amenities` (benches,
tables, planters, bins, ...), :mod:`.nature` (trees, plants, stones, animals), :mod:`.work_play`
(construction gear, sports equipment, a stroller) and :mod:`.carried_items`.

Imports: a family imports the core of :mod:`navverse.assets` (``spec``, ``parts``, ``primitives``,
``fittings``, ``materials``, ``errors``) and nothing else of the library: never another family (of
this package or another) nor the registry :mod:`navverse.assets.library`, which imports the families.
This package imports nothing itself.
"""
