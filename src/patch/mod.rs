//! Patch schemes: CPU construction and reference evaluation, one module per scheme.
