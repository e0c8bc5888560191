//! Catmull-Clark subdivision: rules, refinement, limit masks, exact evaluation, stencil tables.
