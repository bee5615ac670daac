//! Verification case: element_checks (to be written)
