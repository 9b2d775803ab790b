/* The build hash names the sources: 16 lowercase hex digits when built by CMake. */
#include "railbrake/rb_build.h"
#include "railbrake/rb_common.h"
#include "rb_test.h"

#include <string.h>

static void test_build_hash_is_16_hex_digits(void)
{
    const char *hash = rb_build_hash();
    CHECK(strlen(hash) == 16);
    for (const char *c = hash; *c; ++c)
        CHECK((*c >= '0' && *c <= '9') || (*c >= 'a' && *c <= 'f'));
}

int main(void)
{
    test_build_hash_is_16_hex_digits();
    CHECK(strlen(rb_version()) >= 5);
    return rb_test_summary("test_build");
}
