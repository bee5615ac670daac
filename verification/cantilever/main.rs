//! Verification case: cantilever (to be written)
