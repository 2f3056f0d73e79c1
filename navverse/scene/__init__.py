"""The scene contract: annotations, in-memory scenes, USD files, scene directories and BEV pictures.

A scene directory holds ``scene.usdc`` (geometry, semantic labels, physics), ``scene.json``
(:class:`~navverse.scene.annotations.SceneAnnotations`) and ``bev.png``. Stages build a
:class:`~navverse.scene.geometry.Scene` and call :func:`~navverse.scene.directory.write_scene_dir`;
everything downstream calls :func:`~navverse.scene.directory.read_scene` or
:func:`~navverse.scene.directory.read_annotations`.

This file imports nothing: import from the module that defines a name (``navverse.scene.directory``,
``navverse.scene.annotations``, ``navverse.scene.geometry``, ``navverse.scene.bev``,
``navverse.scene.usd``...), so that reading a scene's annotations or fields does not load the USD
and rendering libraries.
"""
