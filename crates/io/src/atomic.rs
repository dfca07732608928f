//! Writing a file so that no failure leaves a wrong one: the bytes go to a
//! hidden temporary beside the target (same file system), which is synced
//! and then renamed over the target, or, when replacing is not allowed,
//! hard-linked to the target's name (which fails if the name exists, with
//! nothing written there) and then removed. An existing file is therefore
//! either the old one or the whole new one, whatever happens (an error, a
//! full disk, a signal, even `kill -9`). The temporaries being written are
//! listed, so that a handler of a terminating signal can remove them
//! ([`remove_temporaries`]); only an uncatchable `kill -9` leaves one. A
//! device or FIFO is written in place (a rename would put a regular file
//! where `/dev/null` was).

use crate::{IoError, Result};
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// The temporaries that exist now. A temporary is created and listed, and
/// placed (or removed) and unlisted, under this lock, so whoever holds it
/// sees every temporary on disk.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Proof that the live temporaries were removed: while it is held no
/// temporary is created or put in place (writers wait), so a process that
/// keeps it until it ends leaves none.
#[derive(Debug)]
pub struct TemporariesRemoved {
    _held: MutexGuard<'static, Vec<PathBuf>>,
}

/// Removes every temporary being written now and stops all writers: for a
/// signal handler that then ends the process; an existing target stays as
/// it was, since only a finished temporary ever replaces it.
pub fn remove_temporaries() -> TemporariesRemoved {
    let held = live();
    for tmp in held.iter() {
        let _ = std::fs::remove_file(tmp);
    }
    TemporariesRemoved { _held: held }
}

/// Writes what `write` produces to `path` (see the module doc); without
/// `overwrite` an existing file is an [`IoError::AlreadyExists`] and stays
/// as it was. Missing parent directories are not created.
pub fn write_atomically(
    path: &Path,
    overwrite: bool,
    write: impl FnOnce(&mut dyn Write) -> Result<()>,
) -> Result<()> {
    if crate::is_special_file(path) {
        let file = OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(|e| IoError::from(e).with_path(path))?;
        let mut w = BufWriter::new(file);
        return write(&mut w)
            .and_then(|()| w.flush().map_err(IoError::from))
            .map_err(|e| e.with_path(path));
    }
    if !overwrite && std::fs::symlink_metadata(path).is_ok() {
        return Err(IoError::AlreadyExists {
            path: path.to_path_buf(),
        });
    }
    let tmp = temporary_beside(path);
    let file = {
        let mut live = live();
        let file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(|e| IoError::from(e).with_path(path))?;
        live.push(tmp.clone());
        file
    };
    let filled = fill(file, write);
    let mut live = live();
    let result = filled.and_then(|()| place(&tmp, path, overwrite));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    live.retain(|p| *p != tmp);
    result.map_err(|e| e.with_path(path))
}

fn fill(file: File, write: impl FnOnce(&mut dyn Write) -> Result<()>) -> Result<()> {
    let mut w = BufWriter::new(file);
    write(&mut w)?;
    w.flush()?;
    w.get_ref().sync_all()?;
    Ok(())
}

/// Puts the finished temporary under the target's name.
fn place(tmp: &Path, path: &Path, overwrite: bool) -> Result<()> {
    if overwrite {
        return std::fs::rename(tmp, path).map_err(IoError::from);
    }
    match std::fs::hard_link(tmp, path) {
        Ok(()) => {
            let _ = std::fs::remove_file(tmp);
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Err(IoError::AlreadyExists {
            path: path.to_path_buf(),
        }),
        // A file system without hard links: the name was free a moment ago.
        Err(_) if std::fs::symlink_metadata(path).is_err() => {
            std::fs::rename(tmp, path).map_err(IoError::from)
        }
        Err(e) => Err(e.into()),
    }
}

/// `dir/.name.trigbody-PID-N.tmp`: hidden, beside the target, unique per
/// process and call.
fn temporary_beside(path: &Path) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static CALLS: AtomicUsize = AtomicUsize::new(0);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".to_string());
    let n = CALLS.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.trigbody-{}-{n}.tmp", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `remove_temporaries` removes every live temporary of the process,
    /// those of a test running beside it too: the tests that write take
    /// turns.
    static TURN: std::sync::Mutex<()> = std::sync::Mutex::new(());

    fn turn() -> std::sync::MutexGuard<'static, ()> {
        TURN.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("trigbody-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn entries(d: &Path) -> usize {
        std::fs::read_dir(d).unwrap().count()
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let _turn = turn();
        let d = dir("fail");
        let p = d.join("a.txt");
        std::fs::write(&p, b"old").unwrap();
        for overwrite in [false, true] {
            let e = write_atomically(&p, overwrite, |w| {
                w.write_all(b"half")?;
                Err(IoError::WrongKind {
                    path: None,
                    message: "failed midway".into(),
                })
            });
            assert!(e.is_err());
            assert_eq!(std::fs::read(&p).unwrap(), b"old");
            assert_eq!(entries(&d), 1, "a temporary was left");
        }
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn replacing_needs_overwrite_and_leaves_nothing_else() {
        let _turn = turn();
        let d = dir("replace");
        let p = d.join("a.txt");
        write_atomically(&p, false, |w| Ok(w.write_all(b"one")?)).unwrap();
        let e = write_atomically(&p, false, |w| Ok(w.write_all(b"two")?)).unwrap_err();
        assert!(matches!(e, IoError::AlreadyExists { .. }), "{e}");
        assert_eq!(std::fs::read(&p).unwrap(), b"one");
        write_atomically(&p, true, |w| Ok(w.write_all(b"two")?)).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert_eq!(entries(&d), 1);
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn a_temporary_is_listed_while_it_is_written_and_removed_on_demand() {
        let _turn = turn();
        let d = dir("live");
        let p = d.join("a.txt");
        std::fs::write(&p, b"old").unwrap();
        let e = write_atomically(&p, true, |w| {
            w.write_all(b"half")?;
            let listed: Vec<PathBuf> = live()
                .iter()
                .filter(|t| t.starts_with(&d))
                .cloned()
                .collect();
            assert_eq!(listed.len(), 1);
            assert!(listed[0].exists());
            drop(remove_temporaries());
            assert!(!listed[0].exists());
            Err(IoError::WrongKind {
                path: None,
                message: "stopped".into(),
            })
        });
        assert!(e.is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        assert_eq!(entries(&d), 1);
        assert!(!live().iter().any(|t| t.starts_with(&d)));
        std::fs::remove_dir_all(d).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_device_is_written_in_place() {
        use std::os::unix::fs::FileTypeExt;
        let _turn = turn();
        write_atomically(Path::new("/dev/null"), false, |w| Ok(w.write_all(b"x")?)).unwrap();
        assert!(std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device());
    }
}
