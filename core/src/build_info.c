/* Build identification: a hash of the core's sources, so a result file can name the exact core
 * that made it. CMake computes RB_BUILD_HASH at configure time (core/CMakeLists.txt); a build
 * without it (an FMU compiled from the shipped sources) reports "unknown". */
#include "railbrake/rb_common.h"

#ifndef RB_BUILD_HASH
#define RB_BUILD_HASH "unknown"
#endif

const char *rb_build_hash(void) { return RB_BUILD_HASH; }
