// The object that owns the test programs' shared precompiled header (tests/CMakeLists.txt):
// CMake compiles the header beside this empty file, and every test target reuses it.
