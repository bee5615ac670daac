//! Verification case: ccx_crosscheck (to be written)
