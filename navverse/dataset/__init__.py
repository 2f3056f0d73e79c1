"""The episode dataset: its schema, deterministic ``.json.gz`` files, the manifest, reading and publishing.

A dataset version is a directory ``episodes/<name>/v<version>/`` (DESIGN.md §3)::

    manifest.json                  format and dataset versions, counts, checksums, scenes, splits
    <split>/<task>.json.gz         {"episodes": [...], "goals_by_category": {...},
                                    "category_to_task_category_id": {...}}
    <split>/<task>.rollouts.json.gz   {episode_id: [[t, x, y, z, qx, qy, qz, qw], ...]}: the
                                    verification rollout of every episode (10 Hz robot base poses)

The package holds one module per job, and re-exports their public API here (``from navverse.dataset
import Episode, Dataset, ...``):

- :mod:`navverse.records.schema`: the episode records (:class:`Episode`, :class:`Goal`,
  :class:`EpisodeFile`...), habitat-lab's layout (``start_position``, ``start_rotation`` as
  ``[x, y, z, w]``, ``goals``, ``reference_path``...), the format version, goal and success
  distances;
- :mod:`navverse.records.jsongz`: ``.json.gz`` files written with sorted keys and a zero gzip time
  stamp, so the same content gives the same bytes, and read decompressed in chunks up to a cap;
- :mod:`.manifest`: :class:`DatasetManifest`, read with a size cap and validated strictly (a ``files``
  entry is a plain ``<split>/<task>[.rollouts].json.gz`` inside the version directory, checksums are
  SHA-256 hex);
- :mod:`.reader`: :class:`Dataset` reads a version and checks its format version;
  :meth:`Dataset.verify` checks the version against its manifest before it is used (the listing,
  regular files only, checksums, the episode counts); an episode or rollouts file is decompressed
  only once its checksum matched, and never beyond :data:`MAX_FILE_BYTES`;
- :mod:`navverse.records.files`: the bounded, checked reading of dataset files that verification uses;
- :mod:`.private`: private splits (``test``): their public episodes withheld, the full ones in a
  private file apart whose SHA-256 the manifest records;
- :mod:`.publish`: :func:`publish` copies a built dataset into ``episodes/`` and refuses to change a
  published version;
- :mod:`.counts`: the manifest's counts table;
- :mod:`navverse.records.errors`: :class:`DatasetError`.

A file's SHA-256 is :func:`navverse.files.file_sha256`, also exported here.
"""

from navverse.dataset.counts import counts_table
from navverse.dataset.manifest import MAX_MANIFEST_BYTES, DatasetManifest
from navverse.dataset.private import PRIVATE_SPLITS
from navverse.dataset.publish import built_version, local_dataset, publish
from navverse.dataset.reader import Dataset
from navverse.files import file_sha256
from navverse.records.errors import DatasetError
from navverse.records.files import MAX_FILE_BYTES
from navverse.records.jsongz import read_json_gz, write_json_gz
from navverse.records.schema import (
    FORMAT_VERSION,
    INSTRUCTION_TYPES,
    PRIVATE_FORMAT_VERSION,
    PUBLIC_FORMAT_VERSION,
    TASKS,
    Episode,
    EpisodeFile,
    EpisodeInfo,
    Goal,
    Instruction,
    InstructionType,
    Landmark,
    Verification,
    goal_distance,
    success_distance,
)

__all__ = [
    "FORMAT_VERSION",
    "INSTRUCTION_TYPES",
    "MAX_FILE_BYTES",
    "MAX_MANIFEST_BYTES",
    "PRIVATE_FORMAT_VERSION",
    "PRIVATE_SPLITS",
    "PUBLIC_FORMAT_VERSION",
    "TASKS",
    "Dataset",
    "DatasetError",
    "DatasetManifest",
    "Episode",
    "EpisodeFile",
    "EpisodeInfo",
    "Goal",
    "Instruction",
    "InstructionType",
    "Landmark",
    "Verification",
    "built_version",
    "counts_table",
    "file_sha256",
    "goal_distance",
    "local_dataset",
    "publish",
    "read_json_gz",
    "success_distance",
    "write_json_gz",
]
