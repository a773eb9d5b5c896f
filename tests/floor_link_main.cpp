// Linked with one bench floor's library whole (every object in it) and only the libraries that floor links: a
// call from that floor into a higher one is an undefined reference here, so the build fails
// (tests/CMakeLists.txt).
int main() { return 0; }
