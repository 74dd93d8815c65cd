//! The check battery (placeholder module: filled by the check work).
