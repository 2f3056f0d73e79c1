"""Toy stages for end-to-end tests of the ``navverse`` command on a throw-away workspace
(``navverse.cli.STAGES_PACKAGE`` pointed here by the test's driver)."""
