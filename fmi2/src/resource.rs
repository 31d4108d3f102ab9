//! `fmuResourceLocation` handling: FMI 2.0 passes a URI (`file:///C:/x`, `file:///home/x`, `file:/x`,
//! `file://localhost/x`), possibly percent-encoded. Our FMUs need no resources yet, but a model that
//! does gets a plain path from here.

use std::path::PathBuf;

/// Converts a `file:` URI to a path. Other schemes, malformed escapes and non-UTF-8 results are errors.
pub fn uri_to_path(uri: &str) -> Result<PathBuf, String> {
    let rest = uri
        .strip_prefix("file:")
        .ok_or_else(|| format!("resource location '{uri}' is not a file: URI"))?;
    let path = if let Some(after) = rest.strip_prefix("//") {
        // file://host/path: only an empty host or localhost refers to this machine.
        let slash = after.find('/').unwrap_or(after.len());
        let host = &after[..slash];
        if !(host.is_empty() || host.eq_ignore_ascii_case("localhost")) {
            return Err(format!(
                "resource location '{uri}' names a remote host '{host}'"
            ));
        }
        &after[slash..]
    } else {
        rest
    };
    if !path.starts_with('/') {
        return Err(format!("resource location '{uri}' is not an absolute path"));
    }
    Ok(PathBuf::from(percent_decode(path)?))
}

fn percent_decode(s: &str) -> Result<String, String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("bad percent escape in '{s}'"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("'{s}' does not decode to UTF-8"))
}

/// Builds a `file:///` URI for a path (percent-encoding what URIs cannot carry), for importers.
pub fn path_to_uri(path: &std::path::Path) -> String {
    let mut uri = String::from("file://");
    for b in path.to_string_lossy().bytes() {
        if b.is_ascii_alphanumeric() || b"/-_.~".contains(&b) {
            uri.push(b as char);
        } else {
            uri.push_str(&format!("%{b:02X}"));
        }
    }
    uri
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_the_usual_forms() {
        assert_eq!(
            uri_to_path("file:///tmp/a%20b/").unwrap(),
            PathBuf::from("/tmp/a b/")
        );
        assert_eq!(uri_to_path("file:/tmp/x").unwrap(), PathBuf::from("/tmp/x"));
        assert_eq!(
            uri_to_path("file://localhost/tmp/x").unwrap(),
            PathBuf::from("/tmp/x")
        );
    }

    #[test]
    fn rejects_the_rest() {
        assert!(uri_to_path("http://x/y").is_err());
        assert!(uri_to_path("file://server/share").is_err());
        assert!(uri_to_path("file:///bad%zz").is_err());
        assert!(uri_to_path("file:relative").is_err());
    }

    #[test]
    fn round_trip() {
        let p = std::path::Path::new("/tmp/dir with space/ü%");
        assert_eq!(uri_to_path(&path_to_uri(p)).unwrap(), p);
    }
}
