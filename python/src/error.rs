//! The exception of an invalid scene.

pyo3::create_exception!(
    penumbra,
    SceneError,
    pyo3::exceptions::PyValueError,
    "An invalid scene or mesh. The message is the command line's: it names the file, \
     line and column (`scene.toml:12:10: objects[1].radius: ...`) or, for a scene made \
     from a dict, the key path. A subclass of ValueError, because a bad scene is bad input."
);
