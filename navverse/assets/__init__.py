"""Parametric object library: category -> coloured, closed triangle mesh of a sampled size.

:mod:`navverse.assets.library` is the entry point (``asset``, ``categories``, ``make_object``; the
local frame every object is built in); :mod:`navverse.assets.errors` has its errors and
:mod:`navverse.assets.primitives` the solids they are made of. The package itself imports nothing,
so that a light submodule (e.g. the primitives) does not load the whole library, and so that the
code hash of a stage covers exactly the asset modules it uses.
"""
