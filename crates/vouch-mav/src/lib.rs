//! vouch-mav
