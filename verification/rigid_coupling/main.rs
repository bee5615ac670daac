//! Verification case: rigid hub coupling (to be written)
