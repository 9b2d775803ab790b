#include "railbrake/rb_build.h"

/* RB_BUILD_HASH is defined for this file only (core/CMakeLists.txt), so a source edit recompiles
 * this one file, not the whole core. */
#ifndef RB_BUILD_HASH
#define RB_BUILD_HASH "unknown"
#endif

const char *rb_build_hash(void) { return RB_BUILD_HASH; }
