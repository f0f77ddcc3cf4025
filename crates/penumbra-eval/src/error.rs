//! What can go wrong, split the way a command line needs it: bad input the
//! user can fix (exit status 2) versus failures of the run itself.

use std::path::PathBuf;

use penumbra::render::RenderError;
use penumbra::scene::SceneError;

#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// The bunny file is missing or cannot be read as a mesh.
    #[error("the Stanford bunny at {}: {reason} (give --bunny PATH or set PENUMBRA_BUNNY)", path.display())]
    Bunny { path: PathBuf, reason: String },
    /// The output directory cannot be created or written.
    #[error("cannot write the report into {}: {reason}", path.display())]
    OutDir { path: PathBuf, reason: String },
    /// A scene variant made by the pipeline did not validate (a bug here, or
    /// a change in the built-in scenes).
    #[error("scene for {job}: {source}")]
    Scene { job: String, source: SceneError },
    #[error("rendering {job}: {source}")]
    Render { job: String, source: RenderError },
    /// The renderer panicked (a bug in the library): reported, not re-raised,
    /// so that the caller can still exit cleanly.
    #[error("rendering {job}: the renderer panicked")]
    Panicked { job: String },
    /// `--study` named no known study.
    #[error("unknown study '{name}' (expected one of: {valid})")]
    UnknownStudy { name: String, valid: String },
    /// Writing an image or a report file failed after the directory checked out.
    #[error("writing {}: {message}", path.display())]
    Write { path: PathBuf, message: String },
}

impl EvalError {
    /// True for errors the user can fix by changing the arguments.
    pub fn is_invalid_input(&self) -> bool {
        matches!(
            self,
            EvalError::Bunny { .. } | EvalError::OutDir { .. } | EvalError::UnknownStudy { .. }
        )
    }
}
