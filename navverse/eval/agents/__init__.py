"""Agents for ``navverse run-agent``: the interface (:mod:`.base`) and the built-in agents."""
