//! Verification case: bad_decks (to be written)
