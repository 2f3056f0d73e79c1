"""Indoor object families: furniture and equipment of homes, offices, schools, shops, cafes and hospitals.

One module per group of categories, each declaring ``ASSETS`` (a tuple of
:class:`~navverse.assets.spec.Asset` whose contexts are indoor ones): :mod:`.seating`, :mod:`.tables`,
:mod:`.storage`, :mod:`.home` (bed, piano), :mod:`.kitchen_bath`, :mod:`.electronics`,
:mod:`.fixtures` (whiteboard, trash can, coat rack, ...), :mod:`.decor`, :mod:`.retail` and
:mod:`.medical`.

Imports: a family imports the core of :mod:`navverse.assets` (``spec``, ``parts``, ``primitives``,
``fittings``, ``materials``, ``errors``) and nothing else of the library: never another family (of
this package or another) nor the registry :mod:`navverse.assets.library`, which imports the families.
This package imports nothing itself.
"""
