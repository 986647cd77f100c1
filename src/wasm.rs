//! wasm-bindgen glue. STUB: being written.
