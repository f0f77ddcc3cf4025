use std::fmt;

/// A failure of the command, classified for the exit status.
#[derive(Debug)]
pub enum CliError {
    /// Bad arguments, scene, mesh or output path: exit status 2.
    Input(String),
    /// Anything else: exit status 1.
    Other(String),
}

impl CliError {
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => 2,
            CliError::Other(_) => 1,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) | CliError::Other(m) => f.write_str(m),
        }
    }
}

/// Shorthand for an input error from anything displayable.
pub fn input(e: impl fmt::Display) -> CliError {
    CliError::Input(e.to_string())
}

/// Shorthand for an internal/environment error from anything displayable.
pub fn other(e: impl fmt::Display) -> CliError {
    CliError::Other(e.to_string())
}
