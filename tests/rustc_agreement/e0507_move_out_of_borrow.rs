// Moving a non-`Copy` field out of a reference.
struct Node {
    child: Child,
}

struct Child {
    id: u32,
}

fn take(n: &Node) -> Child {
    n.child //~ E0507
}

fn trax_main() {
    let n = Node { child: Child { id: 2 } };
    println!("{}", take(&n).id);
}
