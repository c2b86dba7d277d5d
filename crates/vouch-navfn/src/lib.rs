//! vouch-navfn
