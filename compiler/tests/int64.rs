//! Kernels using 64-bit division and conversions link without external helpers.

mod common;

use common::*;
use trax_compiler::Emit;

#[test]
fn int64_helpers_are_defined_locally() {
    let out = scratch("int64");
    let k = crate_dir().join("tests/kernels/int64.rs");
    for opt in [0, 2] {
        let obj = build_obj(&k, opt, &out);
        verify_dwarf(&obj);
        only_trax_undefined(&obj);
        let syms = tool("llvm-objdump", &["-t", obj.to_str().unwrap()]);
        assert!(
            syms.contains("__udivdi3") && syms.contains("__fixdfdi"),
            "-O{opt}:\n{syms}"
        );
    }
}

#[test]
fn kernels_without_int64_division_get_no_helpers() {
    let ir = String::from_utf8(build(
        &crate_dir().join("../examples/hello.rs"),
        2,
        Emit::LlvmIr,
    ))
    .unwrap();
    assert!(
        !ir.contains("__udivdi3"),
        "helpers are only linked on demand"
    );
}
