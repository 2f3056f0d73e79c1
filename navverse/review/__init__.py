"""Manual quality control of a dataset version: the review page and its decisions file.

:mod:`navverse.review.decisions` reads, validates and writes ``<name>.review.yml`` next to the dataset
recipe (what the ``package_dataset`` stage reads); :mod:`navverse.review.server` serves the page;
:mod:`navverse.review.cli` is ``navverse review``. This file imports none of them, so the stage's code
hash covers only the decisions module it imports.
"""
