// Where the tests find the executables and the source tree. Set at configure time in one generated file
// (test_paths.cpp in the build folder), not as compile definitions: every other test file then compiles to
// the same object in any checkout, and a fresh clone's build reuses the compiler cache of another's.
#pragma once

namespace toolinc::testing {

extern const char* const kBinDir;     // the build's bin/: the executables under test
extern const char* const kSourceDir;  // the source tree: configs/, docs/, data/, scripts/

}  // namespace toolinc::testing
