//! Rack-generated tooth profile (in progress).
