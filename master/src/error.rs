//! Why an `airring` command stopped, as a type. Every subcommand returns [`Error`]: the variant
//! says what kind of thing went wrong (a caller, a test or a wrapper script tells a refused input
//! from a failed run without reading the text), the text is the message the user reads.
//!
//! The variants follow the order in which a command meets its inputs: the flags, the files it
//! reads, the folder it writes, the FMUs, the run or analysis itself, its outputs. A command
//! checks all inputs before anything runs, so every error but [`Error::Run`] and
//! [`Error::Output`] leaves nothing behind.

use crate::run::folder::FolderError;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A flag, or a combination of flags, refused before anything ran; the message names the flag.
    #[error("{0}")]
    Flag(String),
    /// An input file refused or unreadable: a design, study, system or optimisation file, a
    /// rotor file, a run folder read back. The message names the file and, where it can, the
    /// table and key.
    #[error("{0}")]
    Input(String),
    /// The output folder refused (it holds a run or a sweep, a live process holds it, ...).
    #[error(transparent)]
    Folder(#[from] FolderError),
    /// The FMUs not found, or a system's FMUs refused before the run started.
    #[error("{0}")]
    Fmus(String),
    /// A run, a study's runs or an analysis could not start, or failed (what a started run
    /// wrote stays).
    #[error("{0}")]
    Run(String),
    /// An output file could not be written.
    #[error("{0}")]
    Output(String),
}

/// Shorthands for classifying a `Result<_, String>` of the library at a command's boundary.
pub trait Classify<T> {
    fn flag(self) -> Result<T, Error>;
    fn input(self) -> Result<T, Error>;
    fn fmus(self) -> Result<T, Error>;
    fn run(self) -> Result<T, Error>;
    fn output(self) -> Result<T, Error>;
}

impl<T, E: std::fmt::Display> Classify<T> for Result<T, E> {
    fn flag(self) -> Result<T, Error> {
        self.map_err(|e| Error::Flag(e.to_string()))
    }
    fn input(self) -> Result<T, Error> {
        self.map_err(|e| Error::Input(e.to_string()))
    }
    fn fmus(self) -> Result<T, Error> {
        self.map_err(|e| Error::Fmus(e.to_string()))
    }
    fn run(self) -> Result<T, Error> {
        self.map_err(|e| Error::Run(e.to_string()))
    }
    fn output(self) -> Result<T, Error> {
        self.map_err(|e| Error::Output(e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_message_is_the_librarys_text_and_the_variant_its_kind() {
        let r: Result<(), String> = Err("--stop = -1 s must be > 0".into());
        let e = r.flag().unwrap_err();
        assert!(matches!(e, Error::Flag(_)));
        assert_eq!(e.to_string(), "--stop = -1 s must be > 0");
        let folder = FolderError::NotAFolder { path: "x".into() };
        let text = folder.to_string();
        let e: Error = folder.into();
        assert!(matches!(e, Error::Folder(FolderError::NotAFolder { .. })));
        assert_eq!(e.to_string(), text, "a folder's refusal reads as before");
    }
}
