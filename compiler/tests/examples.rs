//! Every kernel in `examples/` compiles at -O0 and -O2 with valid DWARF and no
//! `$gp`-relative relocations.

mod common;

use common::*;

#[test]
fn every_example_compiles() {
    let dir = crate_dir().join("../examples");
    let mut kernels: Vec<_> = std::fs::read_dir(&dir)
        .expect("examples dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .collect();
    kernels.sort();
    assert!(!kernels.is_empty(), "no kernels in {}", dir.display());
    let out = scratch("examples");
    for k in &kernels {
        for opt in [0, 2] {
            let obj = build_obj(k, opt, &out);
            verify_dwarf(&obj);
            no_gprel(&obj);
            only_trax_undefined(&obj);
            let syms = tool("llvm-objdump", &["-t", obj.to_str().unwrap()]);
            assert!(
                syms.contains("trax_main"),
                "{}: no trax_main symbol:\n{syms}",
                k.display()
            );
        }
    }
}
