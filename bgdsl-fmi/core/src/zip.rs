//! A minimal ZIP writer: DEFLATE-compressed entries (stored when compression does not
//! pay), with CRC-32 (ISO 3309, the polynomial ZIP uses), which every unzip tool and
//! FMI importer reads.
//!
//! Entries carry a fixed timestamp (1980-01-01 00:00, the earliest ZIP can say), so the
//! same inputs give the same bytes. No ZIP64: entries and offsets must stay under
//! 4 GiB, which [`ZipWriter::add`] checks.

/// Why an archive could not be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ZipError {
    /// An entry or the archive would exceed what ZIP without ZIP64 can say.
    TooLarge {
        /// The entry being added.
        name: String,
    },
    /// An entry name is empty, absolute, has a `\` or a `..` part, or is too long.
    BadName {
        /// The name.
        name: String,
    },
}

impl core::fmt::Display for ZipError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ZipError::TooLarge { name } => {
                write!(
                    f,
                    "adding `{name}` would make the archive larger than 4 GiB"
                )
            }
            ZipError::BadName { name } => write!(
                f,
                "`{name}` is not a valid entry name (relative, `/`-separated, no `..`)"
            ),
        }
    }
}

impl std::error::Error for ZipError {}

/// The CRC-32 table, computed at compile time.
const CRC_TABLE: [u32; 256] = {
    let mut table = [0u32; 256];
    let mut n = 0;
    while n < 256 {
        let mut c = n as u32;
        let mut k = 0;
        while k < 8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
            k += 1;
        }
        table[n] = c;
        n += 1;
    }
    table
};

/// The CRC-32 of `data`, as ZIP (and gzip, PNG) compute it.
pub fn crc32(data: &[u8]) -> u32 {
    let mut c = 0xFFFF_FFFFu32;
    for &b in data {
        c = CRC_TABLE[((c ^ u32::from(b)) & 0xFF) as usize] ^ (c >> 8);
    }
    c ^ 0xFFFF_FFFF
}

/// 1980-01-01 00:00:00 in MS-DOS date and time format.
const DOS_TIME: u16 = 0;
const DOS_DATE: u16 = (1 << 5) | 1;
/// Compression methods.
const STORED: u16 = 0;
const DEFLATE: u16 = 8;
/// Version 2.0 of the format: what DEFLATE needs.
const VERSION: u16 = 20;
/// "Made by" a Unix system (so the external attributes are Unix permissions), 2.0.
const MADE_BY: u16 = (3 << 8) | VERSION;
/// General-purpose flag bit 11: names are UTF-8.
const UTF8_NAMES: u16 = 1 << 11;

struct Entry {
    name: String,
    crc: u32,
    method: u16,
    compressed: u32,
    size: u32,
    offset: u32,
    mode: u32,
}

/// An archive being built in memory.
#[derive(Default)]
pub struct ZipWriter {
    bytes: Vec<u8>,
    entries: Vec<Entry>,
}

impl core::fmt::Debug for ZipWriter {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ZipWriter")
            .field("bytes", &self.bytes.len())
            .field("entries", &self.entries.len())
            .finish()
    }
}

fn put16(out: &mut Vec<u8>, v: u16) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put32(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

impl ZipWriter {
    /// An empty archive.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a file `name` (relative, `/`-separated) holding `data`; `executable` sets
    /// the Unix mode 0755 instead of 0644 (for shared libraries).
    ///
    /// # Errors
    ///
    /// A bad name, or the archive would pass 4 GiB.
    pub fn add(&mut self, name: &str, data: &[u8], executable: bool) -> Result<(), ZipError> {
        let bad_name = name.is_empty()
            || name.starts_with('/')
            || name.contains('\\')
            || name.split('/').any(|part| part.is_empty() || part == "..")
            || name.len() > usize::from(u16::MAX);
        if bad_name {
            return Err(ZipError::BadName {
                name: name.to_string(),
            });
        }
        let too_large = || ZipError::TooLarge {
            name: name.to_string(),
        };
        let offset = u32::try_from(self.bytes.len()).map_err(|_| too_large())?;
        let size = u32::try_from(data.len()).map_err(|_| too_large())?;
        let end = 30 + name.len() as u64 + u64::from(size) + u64::from(offset);
        if end >= u64::from(u32::MAX) || self.entries.len() >= usize::from(u16::MAX) {
            return Err(too_large());
        }
        let crc = crc32(data);
        let deflated = miniz_oxide::deflate::compress_to_vec(data, 6);
        let (method, body) = if deflated.len() < data.len() {
            (DEFLATE, deflated.as_slice())
        } else {
            (STORED, data)
        };
        let compressed = body.len() as u32; // at most `size`
        let b = &mut self.bytes;
        put32(b, 0x0403_4b50); // local file header
        put16(b, VERSION);
        put16(b, UTF8_NAMES);
        put16(b, method);
        put16(b, DOS_TIME);
        put16(b, DOS_DATE);
        put32(b, crc);
        put32(b, compressed);
        put32(b, size);
        put16(b, name.len() as u16);
        put16(b, 0); // extra field length
        b.extend_from_slice(name.as_bytes());
        b.extend_from_slice(body);
        let mode = if executable { 0o100755 } else { 0o100644 };
        self.entries.push(Entry {
            name: name.to_string(),
            crc,
            method,
            compressed,
            size,
            offset,
            mode,
        });
        Ok(())
    }

    /// The archive's bytes: the entries, the central directory and its end record.
    ///
    /// # Errors
    ///
    /// The central directory would pass 4 GiB.
    pub fn finish(mut self) -> Result<Vec<u8>, ZipError> {
        let too_large = || ZipError::TooLarge {
            name: "the central directory".to_string(),
        };
        let start = u32::try_from(self.bytes.len()).map_err(|_| too_large())?;
        let mut directory = Vec::new();
        for e in &self.entries {
            let d = &mut directory;
            put32(d, 0x0201_4b50); // central directory header
            put16(d, MADE_BY);
            put16(d, VERSION);
            put16(d, UTF8_NAMES);
            put16(d, e.method);
            put16(d, DOS_TIME);
            put16(d, DOS_DATE);
            put32(d, e.crc);
            put32(d, e.compressed);
            put32(d, e.size);
            put16(d, e.name.len() as u16);
            put16(d, 0); // extra field length
            put16(d, 0); // comment length
            put16(d, 0); // disk number
            put16(d, 0); // internal attributes
            put32(d, e.mode << 16); // external attributes: Unix mode
            put32(d, e.offset);
            d.extend_from_slice(e.name.as_bytes());
        }
        let size = u32::try_from(directory.len()).map_err(|_| too_large())?;
        if u64::from(start) + u64::from(size) + 22 >= u64::from(u32::MAX) {
            return Err(too_large());
        }
        self.bytes.extend_from_slice(&directory);
        let count = self.entries.len() as u16;
        let b = &mut self.bytes;
        put32(b, 0x0605_4b50); // end of central directory
        put16(b, 0); // this disk
        put16(b, 0); // disk with the directory
        put16(b, count);
        put16(b, count);
        put32(b, size);
        put32(b, start);
        put16(b, 0); // comment length
        Ok(self.bytes)
    }
}

#[cfg(test)]
mod should {
    use super::*;

    #[test]
    fn compute_the_standard_crc_check_value() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(crc32(b""), 0);
    }

    #[test]
    fn lay_out_an_archive_with_its_directory_at_the_end() {
        let mut zip = ZipWriter::new();
        zip.add("a.txt", b"hello", false).unwrap();
        zip.add("dir/b.so", b"\x7fELF", true).unwrap();
        let bytes = zip.finish().unwrap();
        assert_eq!(&bytes[..4], b"PK\x03\x04");
        let end = &bytes[bytes.len() - 22..];
        assert_eq!(&end[..4], b"PK\x05\x06");
        assert_eq!(u16::from_le_bytes([end[10], end[11]]), 2);
        let start = u32::from_le_bytes([end[16], end[17], end[18], end[19]]) as usize;
        assert_eq!(&bytes[start..start + 4], b"PK\x01\x02");
    }

    #[test]
    fn deflate_what_shrinks_and_store_the_rest() {
        let text = "modelDescription ".repeat(100);
        let mut zip = ZipWriter::new();
        zip.add("text", text.as_bytes(), false).unwrap();
        zip.add("tiny", b"x", false).unwrap();
        let bytes = zip.finish().unwrap();
        // The first entry: method 8, and its data inflates back to the text.
        let field = |at: usize| u16::from_le_bytes([bytes[at], bytes[at + 1]]);
        let size32 = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        assert_eq!(field(8), DEFLATE);
        let (compressed, size) = (size32(18), size32(22));
        assert_eq!(size, text.len());
        assert!(compressed < size / 10);
        let data = &bytes[30 + 4..30 + 4 + compressed];
        let inflated = miniz_oxide::inflate::decompress_to_vec(data).unwrap();
        assert_eq!(inflated, text.as_bytes());
        assert_eq!(
            crc32(&inflated),
            u32::from_le_bytes(bytes[14..18].try_into().unwrap())
        );
        // The second: stored, as deflating one byte does not pay.
        let second = 30 + 4 + compressed;
        assert_eq!(field(second + 8), STORED);
        assert_eq!(&bytes[second + 30 + 4..second + 30 + 5], b"x");
    }

    #[test]
    fn refuse_names_that_would_escape_the_archive() {
        let mut zip = ZipWriter::new();
        for name in ["", "/abs", "a/../b", "a\\b", "a//b"] {
            assert!(
                matches!(zip.add(name, b"", false), Err(ZipError::BadName { .. })),
                "{name}"
            );
        }
    }
}
