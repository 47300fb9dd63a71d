fn id<T>(x: T) -> T {
    x
}

fn trax_main() {}
