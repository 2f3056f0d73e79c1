"""Load a habitat export (``navverse.export.export_habitat``) with habitat-lab's own dataset classes.

habitat-lab runs in its own virtual environment (created here if missing, from PyPI), so NavVerse
never imports it. For each split of the export the check loads ``ObjectNavDatasetV1`` and
``VLNDatasetV1`` (habitat-lab's ``ObjectNav-v1`` and ``R2RVLN-v1``) from a ``DatasetConfig`` and
prints the episodes, goals and vocabulary they hold; it fails if a class cannot read a file.

What works (checked on PyPI's releases, without habitat-sim, which is not on PyPI):

- Python 3.11: no release loads. 0.2.4-0.3.2 stop on import in ``default_structured_configs``
  (``ValueError: mutable default ... IteratorOptionsConfig for field iterator_options is not allowed:
  use default_factory``, Python 3.11's dataclass rule), and 0.3.3 imports habitat-sim's ``magnum`` and
  ``habitat_sim`` from ``habitat.tasks.nav.nav``.
- Python 3.10 with habitat-lab 0.3.0 (``0.3.20231024``, the default here): the dataset modules load
  when the ``habitat`` package's own ``__init__`` (which imports the simulator layer, and with it
  ``magnum``) is skipped: the script registers ``habitat`` as a bare package over its installed
  directory, then imports ``habitat.datasets...`` normally. No habitat-lab module is replaced.

Usage::

    python scripts/habitat_check.py --export out/habitat --venv /tmp/habitat-venv \\
        --python /root/.pyenv/versions/3.10.13/bin/python3.10
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
from pathlib import Path

HABITAT_LAB = "0.3.20231024"

_CHILD = r"""
import importlib.util, json, sys, types
from pathlib import Path

spec = importlib.util.find_spec("habitat")
if spec is None:
    sys.exit("habitat-lab is not installed in this environment")
package = types.ModuleType("habitat")  # skip habitat/__init__.py: it imports habitat-sim's magnum
package.__path__ = list(spec.submodule_search_locations)
package.__file__ = spec.origin
sys.modules["habitat"] = package

from omegaconf import OmegaConf
from habitat.config.default_structured_configs import DatasetConfig
from habitat.datasets.object_nav.object_nav_dataset import ObjectNavDatasetV1
from habitat.datasets.vln.r2r_vln_dataset import VLNDatasetV1
from habitat.tasks.nav.object_nav_task import ObjectViewLocation

root = Path(sys.argv[1])
scenes = str(root / "scenes")
result = {}
loaded = {}  # NavVerse episode id -> what habitat-lab read: start position and rotation, goal positions

def config(kind, layout, split):
    path = str(root / layout / "{split}" / "{split}.json.gz")
    return OmegaConf.structured(DatasetConfig(type=kind, split=split, data_path=path, scenes_dir=scenes))

for split_dir in sorted((root / "objectnav_v1").glob("*")):
    data = ObjectNavDatasetV1(config("ObjectNav-v1", "objectnav_v1", split_dir.name))
    goals = [g for e in data.episodes for g in e.goals]
    views = [v for g in goals for v in g.view_points]
    assert all(isinstance(v, ObjectViewLocation) for v in views)
    missing = [e.scene_id for e in data.episodes if not Path(e.scene_id).is_file()]
    for e in data.episodes:
        loaded[e.info["navverse_episode_id"]] = {
            "start_position": list(map(float, e.start_position)),
            "start_rotation": list(map(float, e.start_rotation)),
            "goals": [list(map(float, g.position)) for g in e.goals],
        }
    result[f"ObjectNav-v1 {split_dir.name}"] = {
        "episodes": len(data.episodes), "episodes_without_goals": sum(not e.goals for e in data.episodes),
        "goal_keys": len(data.goals_by_category), "view_points": len(views),
        "categories": len(data.category_to_task_category_id), "scene_glbs_missing": len(missing),
    }
for split_dir in sorted((root / "vln_r2r").glob("*")):
    data = VLNDatasetV1(config("R2RVLN-v1", "vln_r2r", split_dir.name))
    vocab = data.instruction_vocab
    for e in data.episodes:
        loaded[e.info["navverse_episode_id"]] = {
            "start_position": list(map(float, e.start_position)),
            "start_rotation": list(map(float, e.start_rotation)),
            "reference_path": [list(map(float, p)) for p in e.reference_path],
        }
    first = data.episodes[0] if data.episodes else None
    text = " ".join(vocab.idx2word(t) for t in first.instruction.instruction_tokens) if first else ""
    result[f"R2RVLN-v1 {split_dir.name}"] = {
        "episodes": len(data.episodes), "vocabulary": vocab.get_size(), "pad": vocab.PAD_INDEX,
        "unk": vocab.UNK_INDEX, "first_tokens_decoded": text,
    }
print(json.dumps(result, indent=2))
(root / "habitat_loaded.json").write_text(json.dumps(loaded)) if len(sys.argv) > 2 else None
"""


def _python(venv: Path) -> Path:
    return venv / "bin" / "python"


def ensure_venv(venv: Path, *, python: str, version: str) -> None:
    """Create ``venv`` with ``python`` and install habitat-lab ``version`` from PyPI, if it is missing."""
    if _python(venv).exists():
        return
    interpreter = shutil.which(python) or python
    subprocess.run([interpreter, "-m", "venv", str(venv)], check=True)
    install = subprocess.run(
        [str(_python(venv)), "-m", "pip", "install", f"habitat-lab=={version}"],
        capture_output=True,
        text=True,
    )
    if install.returncode != 0:
        sys.stderr.write(install.stdout[-4000:] + install.stderr[-4000:])
        raise SystemExit(f"pip could not install habitat-lab=={version} into {venv} (see its output above)")


def compare(dataset_dir: Path, loaded_file: Path) -> int:
    """Map what habitat-lab loaded back to NavVerse's frame and compare it with the dataset; 0 when
    every position is within 1e-6 m and every heading within 1e-5 rad."""
    import json
    import math

    import numpy as np

    from navverse.dataset import Dataset
    from navverse.export.habitat_scenes import from_habitat, habitat_yaw

    loaded = json.loads(loaded_file.read_text())
    loaded_file.unlink()
    episodes = {e.episode_id: e for e in Dataset(dataset_dir).episodes()}
    position_error = heading_error = 0.0
    for episode_id, seen in loaded.items():
        episode = episodes[episode_id]
        pairs = [(seen["start_position"], episode.start_position)]
        if "reference_path" in seen:
            pairs.append((seen["reference_path"], episode.reference_path))
        for habitat, navverse in pairs:
            gap = np.abs(from_habitat(habitat) - np.asarray(navverse, dtype=float)).max()
            position_error = max(position_error, float(gap))
        turn = float(habitat_yaw(seen["start_rotation"])) - episode.start_yaw
        heading_error = max(heading_error, abs(math.remainder(turn, math.tau)))
    missing = sorted(set(episodes) - set(loaded))
    ok = not missing and position_error <= 1e-6 and heading_error <= 1e-5
    print(
        f"round trip of {len(loaded)} of {len(episodes)} episodes through habitat-lab: largest position "
        f"error {position_error:.1e} m, largest heading error {heading_error:.1e} rad"
        + (f"; not loaded: {', '.join(missing[:5])}" if missing else "")
        + ("" if ok else " — FAILED")
    )
    return 0 if ok else 1


def main(argv: list[str] | None = None) -> int:
    """Run the check; 0 when habitat-lab read every split of the export."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--export", type=Path, required=True, help="a directory written by export_habitat")
    parser.add_argument("--venv", type=Path, default=Path("/tmp/habitat-venv-py310"))
    parser.add_argument("--python", default="python3.10", help="interpreter for a new venv (3.10: see above)")
    parser.add_argument("--habitat-lab", default=HABITAT_LAB, help="habitat-lab version for a new venv")
    parser.add_argument(
        "--dataset",
        type=Path,
        help="the NavVerse dataset version exported: what habitat-lab loaded is mapped back to NavVerse's "
        "frame and compared with it (positions within 1e-6 m, headings within 1e-5 rad)",
    )
    args = parser.parse_args(argv)
    if not (args.export / "export.json").is_file():
        raise SystemExit(f"{args.export} is not a habitat export (no export.json)")
    ensure_venv(args.venv, python=args.python, version=args.habitat_lab)
    dump = [str(args.export.resolve()), *(["dump"] if args.dataset else [])]
    run = subprocess.run([str(_python(args.venv)), "-c", _CHILD, *dump], capture_output=True, text=True)
    sys.stdout.write(run.stdout)
    if run.returncode == 0 and args.dataset is not None:
        return compare(args.dataset, args.export / "habitat_loaded.json")
    if run.returncode != 0:
        sys.stderr.write(run.stderr[-6000:])
        print(
            f"habitat-lab in {args.venv} could not load the export (exit {run.returncode}); on Python "
            "3.11 no PyPI release imports without habitat-sim: use --python python3.10 and a new --venv",
            file=sys.stderr,
        )
    return run.returncode


if __name__ == "__main__":
    raise SystemExit(main())
