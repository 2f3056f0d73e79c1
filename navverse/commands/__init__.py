"""The data and evaluation commands of ``navverse`` (show, validate dataset and submission, eval,
run-agent, export, list), one module per command group declaring its commands' arguments beside
their handlers and adding them with ``register(subparsers, shared)``; :mod:`navverse.cli` assembles
the parser. Shared parser pieces are in :mod:`.common`, dataset and submission helpers in
:mod:`.datasets`, progress output in :mod:`.progress`.

Imports: navverse's library, never ``pipeline``, ``stages`` nor :mod:`navverse.cli` (the build store
comes in :class:`~.common.Shared`). The package imports nothing itself.
"""
