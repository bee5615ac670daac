//! Involute gear relations (ISO 21771).
