//! Writing a file so that no failure leaves a wrong one: the bytes go to a
//! hidden temporary beside the target (same file system), which is synced
//! and then renamed over the target, or, when replacing is not allowed,
//! hard-linked to the target's name (which fails if the name exists, with
//! nothing written there) and then removed. An existing file is therefore
//! either the old one or the whole new one, whatever happens (an error, a
//! full disk, a signal, even `kill -9`); a killed run can leave only the
//! hidden temporary. A device or FIFO is written in place (a rename would
//! put a regular file where `/dev/null` was).

use crate::{IoError, Result};
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

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
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .map_err(|e| IoError::from(e).with_path(path))?;
    let result = fill(file, write).and_then(|()| place(&tmp, path, overwrite));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
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

    #[cfg(unix)]
    #[test]
    fn a_device_is_written_in_place() {
        use std::os::unix::fs::FileTypeExt;
        write_atomically(Path::new("/dev/null"), false, |w| Ok(w.write_all(b"x")?)).unwrap();
        assert!(std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device());
    }
}
