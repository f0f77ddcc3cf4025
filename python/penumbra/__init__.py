"""Penumbra: a CPU stochastic (distributed) ray tracer, from Python.

The API mirrors the ``penumbra`` command line: the same scenes (TOML files,
Mitsuba 3 XML files, built-in names, dicts of the TOML shape or of Mitsuba's
``load_dict`` form), the same render options, the
same pixels and the same statistics document::

    import penumbra

    scene = penumbra.load_scene("showcase")
    image, stats = penumbra.render(scene, width=320, height=240, spp=4)
    penumbra.save_image("showcase.png", image)
    print(stats["rays"]["total"], "rays")

``penumbra.distributed`` renders tiles or animation frames on a Dask cluster
with results identical bit for bit to a local render; it needs ``dask`` and
``distributed`` and is imported on demand. See ``docs/python.md``.
"""

from ._penumbra import (
    DISTRIBUTIONS,
    RENDER_OPTIONS,
    SIMD_SETS,
    Scene,
    SceneError,
    TriangleMesh,
    __version__,
    kernels,
    load_dict,
    load_image,
    load_scene,
    render,
    render_region,
    samples,
    save_image,
    scene_from_dict,
    scenes,
)

__all__ = [
    "DISTRIBUTIONS",
    "RENDER_OPTIONS",
    "SIMD_SETS",
    "Scene",
    "SceneError",
    "TriangleMesh",
    "__version__",
    "kernels",
    "load_dict",
    "load_image",
    "load_scene",
    "render",
    "render_region",
    "samples",
    "save_image",
    "scene_from_dict",
    "scenes",
]
