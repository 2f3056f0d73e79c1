"""navverse.env_spec: what the environment accepts, importable without the simulator, and the same
objects as navverse.env's."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import navverse.env as env
import navverse.env_spec as env_spec


@pytest.mark.parametrize("name", env_spec.__all__)
def test_the_environment_module_gives_the_same_objects(name: str):
    assert getattr(env, name) is getattr(env_spec, name)


def test_it_loads_no_simulator_nor_renderer():
    code = "import sys, json, navverse.env_spec; print(json.dumps(sorted(sys.modules)))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = set(json.loads(done.stdout))
    assert not {m for m in loaded if m.startswith("navverse.sim") or m == "navverse.env"}
    assert not loaded & {"gymnasium", "pybullet", "open3d", "pxr", "trimesh"}


def test_an_unknown_instruction_type_names_the_known_ones():
    with pytest.raises(env_spec.EnvError, match="choose from: category, route, intention"):
        env_spec.check_instruction_type("store")
