// A `use` of something that does not exist.
use trax::nonexistent_module; //~ E0432

fn trax_main() {
    println!("{}", trax::global_id());
}
