//! Wall-clock seconds for the timings in reports; the browser has no system clock for Rust's
//! `std::time`, so wasm asks JavaScript.

/// Seconds since an arbitrary origin.
pub fn now() -> f64 {
    #[cfg(not(target_arch = "wasm32"))]
    {
        use std::time::{SystemTime, UNIX_EPOCH};
        SystemTime::now().duration_since(UNIX_EPOCH).map_or(0.0, |d| d.as_secs_f64())
    }
    #[cfg(target_arch = "wasm32")]
    {
        js_sys::Date::now() / 1000.0
    }
}
