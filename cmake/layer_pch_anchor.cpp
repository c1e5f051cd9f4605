// The object that owns the layers' shared precompiled header (cmake/IllumOptions.cmake,
// illum_layer): CMake compiles the header beside this empty file, and every layer reuses it.
