//! Unit tests of the frictional LTCA kernel.
