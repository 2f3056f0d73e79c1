"""The commands import what their path uses (checked in a fresh interpreter): the command line loads
neither the build engine nor a renderer, and run-agent's parent loads the built-in agents without the
environment module or the camera renderer."""

from __future__ import annotations

import json
import subprocess
import sys

HEAVY = {"open3d", "pxr"}
"""The camera renderer's ray caster and USD: loaded by the commands that render or read geometry."""


def _loaded(code: str) -> set[str]:
    """The modules loaded by ``code`` in a fresh interpreter."""
    program = f"import json, sys\n{code}\nprint(json.dumps(sorted(sys.modules)))"
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, check=True)
    return set(json.loads(done.stdout.splitlines()[-1]))


def test_the_command_line_loads_no_engine_and_no_renderer():
    loaded = _loaded("import navverse.cli\nnavverse.cli.build_parser()")
    assert not {m for m in loaded if m == "pipeline" or m.startswith(("pipeline.", "stages"))}
    assert not loaded & (HEAVY | {"pybullet", "matplotlib", "trimesh"})


def test_loading_the_built_in_agents_loads_no_environment_and_no_renderer():
    loaded = _loaded(
        "from navverse.eval.agents import BUILTIN_AGENTS, load_agent\n"
        "import navverse.eval.runner\n"
        "for name in BUILTIN_AGENTS:\n"
        "    load_agent(name)"
    )
    assert "navverse.env" not in loaded
    assert not loaded & HEAVY
