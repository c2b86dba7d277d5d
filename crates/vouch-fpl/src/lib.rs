//! vouch-fpl
