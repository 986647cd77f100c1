//! The wasm API with the browser APIs the web app relies on: `File` (read whole and in
//! `slice()` chunks), `Blob` (the downloads) and `Worker` (ArrayBuffers transferred, not copied).
//!
//! Browser only (`run_in_browser`): `wasm-pack test --node` leaves it out (wasm-pack sets
//! `WASM_BINDGEN_TEST_ONLY_NODE`, and the runner says it skips a browser-only suite), and
//! scripts/test.sh's wasm tier does not list it; the web tier runs it in chromium:
//!
//! ```text
//! wasm-pack test --headless --chrome -- --test web_wasm
//! ```
//!
//! (`webdriver.json` at the crate root passes `--no-sandbox --headless` to chromium.) No cargo
//! feature gates it, so it shares the wasm tier's build of the crate (a feature would rebuild
//! the crate and every test for wasm32 again).
#![cfg(target_arch = "wasm32")]

use wasm_bindgen::prelude::*;
use wasm_bindgen_futures::JsFuture;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

#[wasm_bindgen(inline_js = r#"
export function make_file(bytes, name) { return new File([bytes], name, { type: 'application/octet-stream' }); }
export function make_blob(bytes) { return new Blob([bytes]); }
export function blob_size(b) { return b.size; }
export function read_blob(b) { return b.arrayBuffer().then((a) => new Uint8Array(a)); }
export function read_slice(f, start, end) { return f.slice(start, end).arrayBuffer().then((a) => new Uint8Array(a)); }
// A worker that sends back what it receives, transferring the buffer both ways. Resolves to
// [echoed bytes, byteLength of the sender's buffer after the transfer].
export function worker_echo(bytes) {
  const src = 'self.onmessage = (e) => self.postMessage(e.data, [e.data.buffer]);';
  const url = URL.createObjectURL(new Blob([src], { type: 'text/javascript' }));
  const w = new Worker(url);
  const copy = new Uint8Array(bytes);
  return new Promise((resolve, reject) => {
    w.onmessage = (e) => { w.terminate(); URL.revokeObjectURL(url); resolve([e.data, copy.buffer.byteLength]); };
    w.onerror = (e) => reject(new Error(e.message));
    w.postMessage(copy, [copy.buffer]);
  });
}
"#)]
extern "C" {
    fn make_file(bytes: &[u8], name: &str) -> JsValue;
    fn make_blob(bytes: &[u8]) -> JsValue;
    fn blob_size(b: &JsValue) -> f64;
    fn read_blob(b: &JsValue) -> js_sys::Promise;
    fn read_slice(f: &JsValue, start: f64, end: f64) -> js_sys::Promise;
    fn worker_echo(bytes: &[u8]) -> js_sys::Promise;
}

async fn bytes_of(p: js_sys::Promise) -> Vec<u8> {
    let v = JsFuture::from(p).await.unwrap();
    js_sys::Uint8Array::new(&v).to_vec()
}

fn warp_options() -> &'static str {
    r#"{"warp":{"spec":{"kind":"conic","angle":30,"direction":"outward","center":[0,0]},"base":null},"max_edge":1,"tolerance":0.01,"layer_height":0.2,"anchor":"auto"}"#
}

fn get(obj: &JsValue, key: &str) -> JsValue {
    js_sys::Reflect::get(obj, &JsValue::from_str(key)).unwrap()
}

#[wasm_bindgen_test]
async fn a_file_read_whole_warps_like_the_bytes_it_holds() {
    let stl = warpslice::wasm::example_stl("cylinder").unwrap();
    let file = make_file(&stl, "cylinder.stl");
    let read = bytes_of(read_blob(&file)).await;
    assert_eq!(read, stl);
    let a = warpslice::wasm::warp(&read, warp_options()).unwrap();
    let b = warpslice::wasm::warp(&stl, warp_options()).unwrap();
    let a = js_sys::Uint8Array::new(&get(&a, "stl")).to_vec();
    let b = js_sys::Uint8Array::new(&get(&b, "stl")).to_vec();
    assert!(a.len() > 84, "a warped binary STL");
    assert_eq!(a, b);
}

#[wasm_bindgen_test]
async fn a_file_read_in_slices_reassembles_exactly() {
    // Odd chunk size so that chunk edges fall inside STL facets.
    let stl = warpslice::wasm::example_stl("sphere").unwrap();
    let file = make_file(&stl, "sphere.stl");
    let chunk = 997.0;
    let mut got = Vec::new();
    let mut off = 0.0;
    while (off as usize) < stl.len() {
        got.extend(bytes_of(read_slice(&file, off, off + chunk)).await);
        off += chunk;
    }
    assert_eq!(got, stl);
}

#[wasm_bindgen_test]
async fn a_blob_of_the_warped_stl_downloads_the_same_bytes() {
    let stl = warpslice::wasm::example_stl("cube").unwrap();
    let out = warpslice::wasm::warp(&stl, warp_options()).unwrap();
    let warped = js_sys::Uint8Array::new(&get(&out, "stl")).to_vec();
    let blob = make_blob(&warped);
    assert_eq!(blob_size(&blob) as usize, warped.len());
    assert_eq!(bytes_of(read_blob(&blob)).await, warped);
    let job = get(&out, "job").as_string().unwrap();
    let job_blob = make_blob(job.as_bytes());
    assert_eq!(bytes_of(read_blob(&job_blob)).await, job.as_bytes());
}

#[wasm_bindgen_test]
async fn a_worker_gets_the_buffer_transferred_not_copied() {
    let stl = warpslice::wasm::example_stl("overhang").unwrap();
    let v = JsFuture::from(worker_echo(&stl)).await.unwrap();
    let arr = js_sys::Array::from(&v);
    let echoed = js_sys::Uint8Array::new(&arr.get(0)).to_vec();
    assert_eq!(echoed, stl);
    assert_eq!(
        arr.get(1).as_f64(),
        Some(0.0),
        "the sender's buffer is detached after the transfer"
    );
}

#[wasm_bindgen_test]
fn the_presets_and_layer_surfaces_glue_answer() {
    let presets = warpslice::wasm::machine_presets().unwrap();
    let v: serde_json::Value = serde_json::from_str(&presets).unwrap();
    assert_eq!(
        v.as_array().unwrap().len(),
        warpslice::machine::preset_names().len()
    );
    let stl = warpslice::wasm::example_stl("cylinder").unwrap();
    let out = warpslice::wasm::warp(&stl, warp_options()).unwrap();
    let job = get(&out, "job").as_string().unwrap();
    let s = warpslice::wasm::layer_surfaces(&job, 5, 16).unwrap();
    assert!(!s.is_empty() && s.len().is_multiple_of(5));
    // Conic 30°: every sample's tilt is 30° (up to the apex).
    let near_30 = s.chunks(5).filter(|c| (c[3] - 30.0).abs() < 1e-6).count();
    assert!(near_30 * 10 >= s.len() / 5 * 9, "most samples tilt 30°");
}
