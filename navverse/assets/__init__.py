"""Parametric object library: category -> coloured, closed triangle mesh of a sampled size.

Layout
------
The core, at the top of the package:

- :mod:`~navverse.assets.library`: the registry and entry point (``asset``, ``categories``,
  ``make_object``; the local frame every object is built in);
- :mod:`~navverse.assets.spec`: what a category is (:class:`~navverse.assets.spec.Asset`, support
  areas, sizes);
- :mod:`~navverse.assets.parts`: closed solid parts and the :class:`~navverse.assets.parts.Assembly`
  that colours and joins them; :mod:`~navverse.assets.primitives`: triangle-mesh boxes, cylinders and
  ramps, also used outside the library;
- :mod:`~navverse.assets.fittings`: legs, handles, fronts and casters shared by indoor and outdoor
  families;
- :mod:`~navverse.assets.materials`: the palettes and :func:`~navverse.assets.materials.pick`, the one
  way every family draws a colour;
- :mod:`~navverse.assets.errors`: the errors a user can cause.

The families, one module per group of categories, each declaring its ``ASSETS``:

- :mod:`navverse.assets.indoor`: furniture and equipment of homes, offices, shops and hospitals;
- :mod:`navverse.assets.outdoor`: streets, parks, construction sites and the things people carry.

And :mod:`navverse.assets.facade`: storefronts set into building facades, with their own place
categories and sign images (not categories of the registry).

Imports
-------
A family imports the core and nothing else of the library: never another family, nor the registry;
the registry imports the families; the core imports no family and not the registry (contracts in
``[tool.importlinter]`` of ``pyproject.toml``). This package and its subpackages import nothing
themselves, so that a light submodule (e.g. the primitives) does not load the whole library, and so
that the code hash of a stage covers exactly the asset modules it uses.
"""
