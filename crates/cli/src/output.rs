//! Writing output files: one policy for every command.
//!
//! * An output is never written over one of the command's inputs, not even
//!   with `--force` (the input is what the output was made from).
//! * An existing file is replaced only with `--force`; without it the
//!   command stops with exit 2 naming the file, before anything is written.
//! * The bytes go to a temporary file beside the target, which is then
//!   renamed over it: a failure (disk full, a killed process) never leaves
//!   half a file under the user's name. Without `--force` the name is first
//!   claimed with `create_new`, so two runs cannot both "create" it.
//! * Missing parent directories are created.
//! * A target that is neither a regular file nor a directory (a device such
//!   as `/dev/null` or `/dev/stdout`, a FIFO) is written in place, with or
//!   without `--force`: writing to it replaces nothing, and a rename would
//!   put a regular file where the device was (it did: `-o /dev/null
//!   --force` turned the machine's `/dev/null` into a file).

use crate::exit::bad;
use anyhow::Result;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Writes `bytes` to `path` under the policy above; `inputs` are the
/// command's input files.
pub fn write_file(path: &Path, bytes: &[u8], inputs: &[&Path], force: bool) -> Result<()> {
    let shown = path.display();
    refuse_input(path, inputs)?;
    if trigbody_io::is_special_file(path) {
        return std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .and_then(|mut f| f.write_all(bytes).and_then(|()| f.flush()))
            .map_err(|e| bad(format!("{shown}: {e}")));
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| bad(format!("{}: {e}", dir.display())))?;
    }
    // Claim the name first when replacing is not allowed.
    let claimed = if force {
        false
    } else {
        std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(|e| {
                if e.kind() == std::io::ErrorKind::AlreadyExists {
                    bad(format!(
                        "{shown}: already exists; use --force to replace it"
                    ))
                } else {
                    bad(format!("{shown}: {e}"))
                }
            })?;
        true
    };
    let tmp = temporary_beside(path);
    let written = std::fs::File::create(&tmp)
        .and_then(|mut f| {
            f.write_all(bytes)?;
            f.sync_all()
        })
        .and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        if claimed {
            let _ = std::fs::remove_file(path);
        }
        return Err(bad(format!("{shown}: {e}")));
    }
    Ok(())
}

/// Exit 2 when `path` names one of `inputs` (for the writers of
/// `trigbody-io`, which keep the rest of the policy themselves).
pub fn refuse_input(path: &Path, inputs: &[&Path]) -> Result<()> {
    if let Ok(target) = path.canonicalize() {
        for input in inputs {
            if input.canonicalize().is_ok_and(|i| i == target) {
                return Err(bad(format!(
                    "{}: refusing to write over the input file",
                    path.display()
                )));
            }
        }
    }
    Ok(())
}

/// `dir/.name.trigbody-PID.tmp`: hidden, beside the target (same file
/// system, so the rename is atomic), unique per process.
fn temporary_beside(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".to_string());
    path.with_file_name(format!(".{name}.trigbody-{}.tmp", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn a_device_is_written_in_place_and_stays_a_device() {
        use std::os::unix::fs::FileTypeExt;
        let null = Path::new("/dev/null");
        assert!(trigbody_io::is_special_file(null));
        for force in [false, true] {
            write_file(null, b"model", &[], force).unwrap();
            let kind = std::fs::metadata(null).unwrap().file_type();
            assert!(kind.is_char_device(), "/dev/null was replaced");
        }
        assert!(!trigbody_io::is_special_file(Path::new("Cargo.toml")));
        assert!(!trigbody_io::is_special_file(Path::new(".")));
    }

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("trigbody-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn new_file_is_written_and_an_existing_one_needs_force() {
        let d = dir("force");
        let p = d.join("sub").join("a.txt");
        write_file(&p, b"one", &[], false).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"one");
        let e = write_file(&p, b"two", &[], false).unwrap_err();
        assert!(e.to_string().contains("already exists"), "{e}");
        assert_eq!(std::fs::read(&p).unwrap(), b"one");
        write_file(&p, b"two", &[], true).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(p.parent().unwrap()).unwrap().count(), 1);
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn the_input_is_never_replaced_even_with_force() {
        let d = dir("input");
        let p = d.join("in.obj");
        std::fs::write(&p, b"v 0 0 0").unwrap();
        let same = d.join(".").join("in.obj");
        for force in [false, true] {
            let e = write_file(&same, b"x", &[&p], force).unwrap_err();
            assert!(e.to_string().contains("input file"), "{e}");
        }
        assert_eq!(std::fs::read(&p).unwrap(), b"v 0 0 0");
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn a_failed_write_leaves_nothing() {
        let d = dir("fail");
        // A directory where the file should go: the rename fails.
        let p = d.join("taken");
        std::fs::create_dir(&p).unwrap();
        assert!(write_file(&p, b"x", &[], true).is_err());
        assert!(p.is_dir());
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(d).unwrap();
    }
}
