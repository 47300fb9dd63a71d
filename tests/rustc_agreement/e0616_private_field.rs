// A private field of a struct in another module.
mod film {
    pub struct Film {
        count: u32,
    }

    impl Film {
        pub fn new() -> Film {
            Film { count: 0 }
        }
    }
}

fn trax_main() {
    let f = film::Film::new();
    println!("{}", f.count); //~ E0616
}
