// Assigning to something that is not a place.
const LIMIT: u32 = 4;

fn trax_main() {
    LIMIT = 5; //~ E0070
    println!("{}", LIMIT);
}
