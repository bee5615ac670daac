//! Verification case: lame_cylinder (to be written)
