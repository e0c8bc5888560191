//! Mesh topology: edges, ordered one-rings, boundaries, per-face classification.
