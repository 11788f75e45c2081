// The source of the tests' precompiled headers (tests/CMakeLists.txt): it compiles them once.
