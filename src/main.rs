fn main() {
    println!("audit: under construction");
}
