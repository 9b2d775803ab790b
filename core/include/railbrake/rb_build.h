#ifndef RB_BUILD_H
#define RB_BUILD_H

#ifdef __cplusplus
extern "C" {
#endif

/* Hash of the C core's sources (core/src, core/include), 16 hex digits of their SHA-256 computed
 * by CMake at configure time; "unknown" when built without CMake. Two libraries with the same hash
 * were built from the same sources, so a report can name exactly which core produced it. */
const char *rb_build_hash(void);

#ifdef __cplusplus
}
#endif

#endif
