//! Write-then-rename, so that readers see the old file or the whole new one.
//!
//! Several files that belong together (a result and its mesh) are written in
//! a [`Batch`]: each goes to a temporary name, and only when all are complete
//! are they renamed into place, the first-named last, so an interrupted
//! solve leaves the old pair or the new one, never one of each. Temporaries
//! in flight are registered, so that a signal handler can remove them
//! ([`remove_temporaries`]).
//!
//! Files are not `fsync`ed: the rename is what keeps a reader, a failed
//! run or an interrupted one from seeing part of a file; surviving a power
//! cut right after the write is left to the file system, as Open CASCADE's
//! and gmsh's writers and `cp` leave it. An fsync cost 0.6–0.8 ms of a
//! 10 ms `fairsurf fill` (session 34, ext4). What that gives up: a write
//! error the file system reports only at fsync or close (NFS, some quota
//! and full-disk cases) goes unnoticed, and the rename then puts the
//! short file in place.

use crate::{Error, Result};
use std::cell::RefCell;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Temporary files being written or waiting for their rename.
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

thread_local! {
    /// The open batch of this thread: (temporary, final path) pairs.
    static STAGED: RefCell<Option<Vec<(PathBuf, PathBuf)>>> = const { RefCell::new(None) };
}

fn register(tmp: &Path) {
    if let Ok(mut t) = TEMPORARIES.lock() {
        t.push(tmp.to_path_buf());
    }
}

fn unregister(tmp: &Path) {
    if let Ok(mut t) = TEMPORARIES.lock() {
        t.retain(|p| p != tmp);
    }
}

/// Removes every temporary file still in flight (for a SIGINT/SIGTERM
/// handler: the outputs keep their old contents).
pub fn remove_temporaries() {
    if let Ok(t) = TEMPORARIES.lock() {
        for p in t.iter() {
            let _ = std::fs::remove_file(p);
        }
    }
}

/// Files written together: while a batch is open on a thread, that thread's
/// [`write_atomic`] calls leave their complete temporaries in place, and
/// [`Batch::commit`] renames them all; a batch dropped without commit (an
/// error, a panic) removes them, leaving every old file as it was.
#[derive(Debug)]
pub struct Batch {
    done: bool,
}

impl Batch {
    /// Opens a batch on this thread (one at a time).
    pub fn begin() -> Self {
        STAGED.with(|s| *s.borrow_mut() = Some(Vec::new()));
        Batch { done: false }
    }

    /// Renames every staged file into place, in reverse order of writing
    /// (the first file written, usually the result, appears last).
    pub fn commit(mut self) -> Result<()> {
        self.done = true;
        let staged = STAGED.with(|s| s.borrow_mut().take()).unwrap_or_default();
        let mut result = Ok(());
        for (tmp, path) in staged.into_iter().rev() {
            if result.is_ok() {
                if let Err(source) = std::fs::rename(&tmp, &path) {
                    result = Err(Error::Write { path, source });
                }
            }
            let _ = std::fs::remove_file(&tmp);
            unregister(&tmp);
        }
        result
    }
}

impl Drop for Batch {
    fn drop(&mut self) {
        if self.done {
            return;
        }
        for (tmp, _) in STAGED.with(|s| s.borrow_mut().take()).unwrap_or_default() {
            let _ = std::fs::remove_file(&tmp);
            unregister(&tmp);
        }
    }
}

/// Writes `path` by calling `fill` on a temporary file in the same directory
/// and renaming it over `path` once complete (inside a [`Batch`]: when the
/// batch commits). On any error the temporary file is removed and `path` is
/// untouched.
pub fn write_atomic(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let werr = |source| Error::Write {
        path: path.to_path_buf(),
        source,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| werr(std::io::Error::other("not a file name")))?;
    let tmp = dir.join(format!(
        ".{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    register(&tmp);
    let staged = STAGED.with(|s| s.borrow().is_some());
    let result = (|| {
        let file = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(file);
        fill(&mut w)?;
        w.into_inner().map_err(|e| e.into_error())?;
        if staged {
            return Ok(());
        }
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        unregister(&tmp);
        return Err(werr(e));
    }
    if staged {
        STAGED.with(|s| {
            if let Some(v) = s.borrow_mut().as_mut() {
                v.push((tmp, path.to_path_buf()));
            }
        });
    } else {
        unregister(&tmp);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failure_leaves_nothing_and_keeps_the_old_file() {
        let dir = std::env::temp_dir().join(format!("fairsurf-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("out.txt");
        write_atomic(&p, |w| w.write_all(b"old")).unwrap();
        let err = write_atomic(&p, |w| {
            w.write_all(b"partial")?;
            Err(std::io::Error::other("disk on fire"))
        });
        assert!(matches!(err, Err(Error::Write { .. })));
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "old");
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(left.len(), 1, "no temporary file left behind");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A batch leaves nothing until it commits, then both files; a batch
    /// that is dropped leaves the old files and no temporary.
    #[test]
    fn a_batch_writes_all_or_nothing() {
        let dir = std::env::temp_dir().join(format!("fairsurf-batch-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (a, b) = (dir.join("a.json"), dir.join("a.obj"));
        write_atomic(&a, |w| w.write_all(b"old a")).unwrap();
        write_atomic(&b, |w| w.write_all(b"old b")).unwrap();
        {
            let _batch = Batch::begin();
            write_atomic(&a, |w| w.write_all(b"new a")).unwrap();
            write_atomic(&b, |w| w.write_all(b"new b")).unwrap();
            assert_eq!(std::fs::read_to_string(&a).unwrap(), "old a");
            // dropped: an error after the writes
        }
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "old a");
        assert_eq!(std::fs::read_to_string(&b).unwrap(), "old b");
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            2,
            "no temporaries"
        );
        let batch = Batch::begin();
        write_atomic(&a, |w| w.write_all(b"new a")).unwrap();
        write_atomic(&b, |w| w.write_all(b"new b")).unwrap();
        batch.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "new a");
        assert_eq!(std::fs::read_to_string(&b).unwrap(), "new b");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        // None of this batch's temporaries is still registered (other
        // tests of this binary write files at the same time: the list as a
        // whole need not be empty).
        assert!(!TEMPORARIES
            .lock()
            .unwrap()
            .iter()
            .any(|t| t.starts_with(&dir)));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn missing_directory_is_a_write_error() {
        let err = write_atomic(Path::new("/nonexistent-dir-fairsurf/x.json"), |w| {
            w.write_all(b"x")
        });
        assert!(matches!(err, Err(Error::Write { .. })));
    }
}
