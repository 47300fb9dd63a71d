#[no_std_please]
fn helper() {}

fn trax_main() {}
