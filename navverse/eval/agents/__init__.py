"""Agents for ``navverse run-agent``: the interface (:mod:`.base`), the built-in agents and their loader.

:func:`load_agent` turns what a user types after ``--agent`` into an agent: a built-in name
(:data:`BUILTIN_AGENTS`), ``package.module:Class``, or ``path/to/file.py:Class``. The class (or any
callable) is called without arguments.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from navverse.env_spec import ACTION_MODES
from navverse.errors import NavverseError

__all__ = ["BUILTIN_AGENTS", "AgentLoadError", "agent_factory", "load_agent"]

BUILTIN_AGENTS = {
    "oracle": "navverse.eval.agents.ground_truth:OracleAgent",
    "gt_goal": "navverse.eval.agents.ground_truth:GTGoalAgent",
    "random": "navverse.eval.agents.random_actions:RandomAgent",
    "frontier": "navverse.eval.agents.frontier:FrontierAgent",
}
"""Built-in agent names and where they live."""


class AgentLoadError(NavverseError):
    """An ``--agent`` that names nothing loadable, or loads something that is not an agent."""


def _module_from(spec: str, name: str) -> Any:
    if spec.endswith(".py") or "/" in spec or "\\" in spec:
        path = Path(spec)
        if not path.is_file():
            raise AgentLoadError(f"agent file {path} does not exist")
        module_name = f"navverse_user_agent_{path.stem}"
        loader_spec = importlib.util.spec_from_file_location(module_name, path)
        if loader_spec is None or loader_spec.loader is None:
            raise AgentLoadError(f"cannot import {path} as a Python module")
        module = importlib.util.module_from_spec(loader_spec)
        sys.modules[module_name] = module
        loader_spec.loader.exec_module(module)
        return module
    try:
        return importlib.import_module(spec)
    except ModuleNotFoundError as exc:
        raise AgentLoadError(
            f"cannot import module {spec!r} for agent {name!r} ({exc}); give a built-in name "
            f"({', '.join(BUILTIN_AGENTS)}), an importable 'module:Class' or 'path/to/file.py:Class'"
        ) from None


def agent_factory(name: str) -> Callable[[], Any]:
    """The class (or factory) an ``--agent`` value names.

    Parameters
    ----------
    name : str
        A key of :data:`BUILTIN_AGENTS`, ``module:Class`` or ``file.py:Class``.

    Raises
    ------
    AgentLoadError
        When the module or attribute does not exist.
    """
    spec = BUILTIN_AGENTS.get(name, name)
    if ":" not in spec:
        raise AgentLoadError(
            f"unknown agent {name!r}: give a built-in name ({', '.join(BUILTIN_AGENTS)}), "
            "'module:Class' or 'path/to/file.py:Class'"
        )
    module_spec, _, attribute = spec.rpartition(":")
    module = _module_from(module_spec, name)
    factory = getattr(module, attribute, None)
    if not callable(factory):
        raise AgentLoadError(f"{module_spec} has no class or function {attribute!r} (agent {name!r})")
    return factory


def load_agent(name: str) -> Any:
    """An agent instance for an ``--agent`` value, checked against the interface.

    Raises
    ------
    AgentLoadError
        When it cannot be loaded, or lacks ``action_mode``, ``reset`` or ``act``.
    """
    agent = agent_factory(name)()
    mode = getattr(agent, "action_mode", None)
    if mode not in ACTION_MODES:
        raise AgentLoadError(
            f"agent {name!r} has action_mode {mode!r}; it must be one of {', '.join(ACTION_MODES)}"
        )
    for method in ("reset", "act"):
        if not callable(getattr(agent, method, None)):
            raise AgentLoadError(f"agent {name!r} has no {method}() method (see navverse.eval.agents.base)")
    return agent
