//! Verification case: nafems_le10 (to be written)
