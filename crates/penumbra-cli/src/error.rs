use std::fmt;

/// A failure of the command, classified for the exit status.
#[derive(Debug)]
pub enum CliError {
    /// Bad arguments, scene, mesh or output path: exit status 2.
    Input(String),
    /// Anything else: exit status 1.
    Other(String),
    /// Ended by a signal after writing what it had: 128 + the signal's
    /// number (130 for SIGINT, 143 for SIGTERM).
    Signal(u8, String),
}

impl CliError {
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => 2,
            CliError::Other(_) => 1,
            CliError::Signal(code, _) => *code,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) | CliError::Other(m) | CliError::Signal(_, m) => f.write_str(m),
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
