//! Kinematic models of modular robots (ATRON, M-TRAN) and their configurations.
