// Host of the RTT layer's precompiled headers (cmake/TactilePch.cmake): the
// headers come in through CMake's -include; this file adds nothing.
int main() { return 0; }
