//! The CPU renderer (placeholder module: filled by the render work).
