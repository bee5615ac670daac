//! Verification case: convergence (to be written)
