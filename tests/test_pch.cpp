// SPDX-License-Identifier: MIT
// The unit the test executables' shared precompiled header is compiled with (softbench_test_pch
// in tests/CMakeLists.txt): the header is built once and every test executable reuses it.
