//! Writing files whole: a temporary file beside the target, synced, renamed over it, the folder
//! synced, so a crash or a full disk leaves the old content or the new one, never a part.
//!
//! Nothing here writes or deletes through a symbolic link: a run folder on a cluster's scratch
//! space may hold links (left by a user, or planted), and following one would write into another
//! run's files or delete them. Files are created exclusively (`O_CREAT | O_EXCL`, which refuses an
//! existing link instead of following it) and renamed into place (a rename replaces a link, it
//! does not write into its target); files opened to append are opened with `O_NOFOLLOW`.

use std::fs::{File, OpenOptions};
use std::io;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};

/// `path` with `.tmp` appended to its file name (in the same folder, so the rename is atomic).
pub fn temporary_name(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}

/// True if `path` itself is a symbolic link (whatever it points to, or to nothing).
pub fn is_symlink(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
}

/// Creates `path` as a new, empty file for writing, replacing what stands there: an old file or a
/// symbolic link is removed first (a link itself, never its target), a folder is an error. The
/// file is created exclusively, so a link put there in between is refused, not followed.
pub fn create_replacing(path: &Path) -> io::Result<File> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.is_dir() => {
            return Err(io::Error::other(format!(
                "{} is a folder, not a file",
                path.display()
            )))
        }
        Ok(_) => std::fs::remove_file(path)?,
        Err(e) if e.kind() == io::ErrorKind::NotFound => {}
        Err(e) => return Err(e),
    }
    OpenOptions::new().write(true).create_new(true).open(path)
}

/// Opens an existing file for writing (to append to it, or cut it) without following a symbolic
/// link: a link at `path` is an error naming it.
pub fn open_existing_for_writing(path: &Path) -> io::Result<File> {
    OpenOptions::new()
        .write(true)
        .custom_flags(libc::O_NOFOLLOW)
        .open(path)
        .map_err(|e| {
            if e.raw_os_error() == Some(libc::ELOOP) {
                io::Error::other(format!(
                    "{} is a symbolic link: AirRing does not write through links in a run \
                     folder (remove the link)",
                    path.display()
                ))
            } else {
                e
            }
        })
}

/// Makes `dir` a real folder for writing into: creates it if missing; a symbolic link there is
/// an error (what is written or removed inside would land in the link's target).
pub fn real_folder(dir: &Path) -> io::Result<()> {
    if is_symlink(dir) {
        return Err(io::Error::other(format!(
            "{} is a symbolic link: AirRing does not write or delete through links in a run \
             folder (remove the link)",
            dir.display()
        )));
    }
    std::fs::create_dir_all(dir)
}

/// Writes `bytes` to `path` whole or not at all. On failure the temporary file is removed (on a
/// full disk it would only take the space the next attempt needs) and `path` is as it was. A
/// symbolic link at `path` is replaced by the file, not written through.
pub fn write_whole(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_whole_with(path, |f| {
        use io::Write;
        f.write_all(bytes)
    })
}

/// As [`write_whole`], with the content written by `fill` into the temporary file.
pub fn write_whole_with(
    path: &Path,
    fill: impl FnOnce(&mut File) -> io::Result<()>,
) -> io::Result<()> {
    let tmp = temporary_name(path);
    let written = create_replacing(&tmp).and_then(|mut f| {
        fill(&mut f)?;
        f.sync_all()
    });
    if let Err(e) = written.and_then(|()| std::fs::rename(&tmp, path)) {
        // (A folder under that name stays: remove_file does not remove folders.)
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        File::open(parent)?.sync_all()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("cosim-files-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_link_at_the_target_or_its_temporary_name_is_replaced_not_followed() {
        let d = folder("links");
        let victim = d.join("victim.txt");
        std::fs::write(&victim, "theirs").unwrap();
        std::os::unix::fs::symlink(&victim, d.join("out.txt")).unwrap();
        std::os::unix::fs::symlink(&victim, d.join("other.txt.tmp")).unwrap();
        write_whole(&d.join("out.txt"), b"ours").unwrap();
        write_whole(&d.join("other.txt"), b"ours too").unwrap();
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "theirs");
        assert!(!is_symlink(&d.join("out.txt")));
        assert_eq!(std::fs::read_to_string(d.join("out.txt")).unwrap(), "ours");
        assert_eq!(
            std::fs::read_to_string(d.join("other.txt")).unwrap(),
            "ours too"
        );
        assert!(!d.join("other.txt.tmp").exists());
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn create_replacing_removes_a_link_and_appending_refuses_one() {
        let d = folder("create");
        let victim = d.join("victim.csv");
        std::fs::write(&victim, "theirs").unwrap();
        let link = d.join("series.csv");
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        let e = open_existing_for_writing(&link).unwrap_err();
        assert!(e.to_string().contains("symbolic link"), "{e}");
        drop(create_replacing(&link).unwrap());
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "theirs");
        assert!(!is_symlink(&link));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_linked_folder_is_refused() {
        let d = folder("dir");
        std::fs::create_dir_all(d.join("target")).unwrap();
        std::os::unix::fs::symlink(d.join("target"), d.join("checkpoint")).unwrap();
        assert!(real_folder(&d.join("checkpoint")).is_err());
        real_folder(&d.join("fresh")).unwrap();
        assert!(d.join("fresh").is_dir());
        let _ = std::fs::remove_dir_all(&d);
    }
}
