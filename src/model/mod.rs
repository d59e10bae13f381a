//! Cross-referenced model (in progress).
