//! Cross-crate tests of the workspace live in `tests/tests/`. This library holds
//! shared test support once more than one test file needs it.
