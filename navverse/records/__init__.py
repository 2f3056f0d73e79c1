"""Episode records and their files: the part of the dataset format that the stages making episodes use.

The episode schema (:mod:`.schema`), deterministic ``.json.gz`` files (:mod:`.jsongz`), the bounded,
checked reading of dataset files (:mod:`.files`) and :class:`~.errors.DatasetError`. They live apart
from :mod:`navverse.dataset` (the reader, the manifest, publishing, private splits), which re-exports
them, and this ``__init__`` imports nothing: the code hash of a stage covers every module its imports
reach, package ``__init__`` files included, so sampling, verification and instructions, which import
only these modules, are not made again when the dataset reader changes.
"""
