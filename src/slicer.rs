//! Driving the real planar slicers installed on this machine (native only). STUB: being written.
