//! The options of the `.vtu` files of a result: their encoding ([`VtuFormat`]) and whether the
//! bodies of one result go into one file each or into one file together ([`VtuLayout`]).

use serde::{Deserialize, Serialize};

/// How the data arrays of a `.vtu` file are stored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum VtuFormat {
    /// Every array as text inside its `DataArray` element (an array holding a non-finite value
    /// excepted, see [`crate::vtu`]), for those who read or diff the files.
    Ascii,
    /// Every array as little-endian raw bytes in one `<AppendedData encoding="raw">` section at
    /// the end of the file, each preceded by its `UInt64` byte count (0.58 of the ASCII size on
    /// the notch at 1000 × 500 cells per body, written in about half the time of ASCII).
    Binary,
    /// The appended section of [`VtuFormat::Binary`] with every array cut into blocks of
    /// [`ZLIB_BLOCK`] bytes, each compressed by zlib at level [`ZLIB_LEVEL`], as VTK's
    /// `vtkZLibDataCompressor` writes it (the default: 0.27 of the ASCII size on the notch at
    /// 1000 × 500 cells per body, written in three quarters of the time of ASCII;
    /// `scripts/vtu_encodings.py` measures it, docs/outputs.md has the table).
    #[default]
    Zlib,
}

/// The uncompressed size of the blocks of a [`VtuFormat::Zlib`] array (the last one may be
/// shorter): 32 KiB, VTK's own. Blocks of up to 1 MiB save less than 0.3 % of the raw bytes on
/// the notch and leave fewer pieces to share between threads.
pub const ZLIB_BLOCK: usize = 1 << 15;

/// The zlib compression level of [`VtuFormat::Zlib`]. Level 1 of the zlib-rs back end codes
/// with static Huffman tables only: on the notch's arrays it leaves 0.54 of the raw bytes
/// against 0.46 at level 2, which takes about twice its time (still a fraction of writing
/// ASCII); levels 3 to 6 gain less than 1 % more at up to twice level 2's time.
pub const ZLIB_LEVEL: u32 = 2;

impl VtuFormat {
    /// The name of the format in problem files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            VtuFormat::Ascii => "ascii",
            VtuFormat::Binary => "binary",
            VtuFormat::Zlib => "zlib",
        }
    }
}

impl std::fmt::Display for VtuFormat {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A VTU format name that is not `ascii`, `binary` or `zlib`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown VTU format '{0}': expected 'zlib', 'binary' or 'ascii'")]
pub struct UnknownVtuFormat(pub String);

impl std::str::FromStr for VtuFormat {
    type Err = UnknownVtuFormat;

    fn from_str(s: &str) -> Result<VtuFormat, UnknownVtuFormat> {
        match s {
            "ascii" => Ok(VtuFormat::Ascii),
            "binary" => Ok(VtuFormat::Binary),
            "zlib" => Ok(VtuFormat::Zlib),
            other => Err(UnknownVtuFormat(other.to_string())),
        }
    }
}

/// How the bodies of one result (one load step) are laid out in `.vtu` files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum VtuLayout {
    /// One file per body, `<body>.vtu` (`<body>-step<k>.vtu` per load step), each with one
    /// `Piece` (the default).
    #[default]
    PerBody,
    /// One file for all bodies, [`COLLECTION_STEM`]`.vtu` (`bodies-step<k>.vtu` per load step),
    /// holding each body as its own `Piece`, in the order of the model's bodies, with the arrays
    /// of its per-body file. One process writes it: a distributed solve over several MPI ranks
    /// refuses it ([`CollectionOverRanks`]).
    Collection,
}

/// The file stem of the [`VtuLayout::Collection`] file of a result: `bodies.vtu`, or
/// `bodies-step<k>.vtu` for load step k.
pub const COLLECTION_STEM: &str = "bodies";

impl VtuLayout {
    /// The name of the layout in problem files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            VtuLayout::PerBody => "per-body",
            VtuLayout::Collection => "collection",
        }
    }
}

impl std::fmt::Display for VtuLayout {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A VTU layout name that is not `per-body` or `collection`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown VTU layout '{0}': expected 'per-body' or 'collection'")]
pub struct UnknownVtuLayout(pub String);

impl std::str::FromStr for VtuLayout {
    type Err = UnknownVtuLayout;

    fn from_str(s: &str) -> Result<VtuLayout, UnknownVtuLayout> {
        match s {
            "per-body" => Ok(VtuLayout::PerBody),
            "collection" => Ok(VtuLayout::Collection),
            other => Err(UnknownVtuLayout(other.to_string())),
        }
    }
}

/// The [`VtuLayout::Collection`] layout asked of a solve over several MPI ranks, each of which
/// holds only its own bodies' fields: the one file would need every body's fields in one process.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "vtu-layout = \"collection\" writes every body into one .vtu file, which needs all the \
     bodies' fields in one process, but this solve runs on more than one MPI rank: run it on \
     one rank, or write one file per body (--vtu-layout per-body, or vtu-layout = \"per-body\" \
     in [output])"
)]
pub struct CollectionOverRanks;

/// How the `.vtu` files of a result are written: their encoding and their layout.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct VtuOptions {
    /// The encoding of every array.
    pub format: VtuFormat,
    /// One file per body or one for all.
    pub layout: VtuLayout,
}

impl From<VtuFormat> for VtuOptions {
    /// `format` with the default layout, one file per body.
    fn from(format: VtuFormat) -> VtuOptions {
        VtuOptions {
            format,
            layout: VtuLayout::default(),
        }
    }
}
