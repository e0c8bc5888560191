//! Feature-adaptive subdivision on the GPU (Köbler 2013, chapter 4; Nießner et al. 2012): for
//! now the compute refinement that applies `subdiv::tables` level by level.

pub mod refine;
