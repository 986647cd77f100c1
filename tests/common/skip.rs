//! The one skip rule of the suite: a tier that cannot run here (a slicer or the corpus is
//! missing) **fails** with the reason, unless `WARPSLICE_ALLOW_SKIP=1` is set (local runs
//! only; `.ci/run` unsets it), in which case it prints that it skipped and why.

/// Whether skipping is allowed (`WARPSLICE_ALLOW_SKIP=1`).
pub fn allowed() -> bool {
    std::env::var("WARPSLICE_ALLOW_SKIP").as_deref() == Ok("1")
}

/// Skip `what` because of `why` when allowed (printing it), else fail the test.
pub fn skip_or_fail(what: &str, why: &str) {
    if allowed() {
        println!("SKIPPED {what}: {why}");
    } else {
        panic!("{what} cannot run: {why} (WARPSLICE_ALLOW_SKIP=1 skips it in a local run)");
    }
}
