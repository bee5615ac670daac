//! Verification case: patch_test (to be written)
