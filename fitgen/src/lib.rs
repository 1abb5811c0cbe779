//! # fitgen — derives the fits and look-up tables in `luts/`
//!
//! Not implemented yet (issue "fitgen + luts/"). Planned: subcommands `list`, `all`,
//! one per table/fit, `--check` (regenerate in memory, compare byte for byte with the
//! committed `luts/`), `--plots DIR`, `--only` to generate what a configuration
//! needs. The integrands and models live in `sbf`; this crate holds only the
//! optimisation drivers and file output.
