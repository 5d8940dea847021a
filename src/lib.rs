//! quadlay: quad remeshing from a user-drawn coarse layout, after Bommes, Vossemer and
//! Kobbelt, *Quadrangular Parameterization for Reverse Engineering* (2008).
//!
//! Data flows one way: bytes → [`io`] → [`mesh`] → layout → parameterization → quads →
//! [`io`] → bytes. The same core runs natively (the `quadlay` command) and in the browser
//! (`wasm`, built for `wasm32-unknown-unknown`).

pub mod clock;
pub mod culprits;
pub mod field;
pub mod geom;
pub mod guidance;
pub mod io;
pub mod layout;
pub mod mesh;
pub mod param;
pub mod quad;
pub mod quote;
pub mod report;
pub mod solve;
pub mod summary;
pub mod verdict;

#[cfg(target_arch = "wasm32")]
mod wasm;
