/* The build hash of a CMake build: 64 lower-case hexadecimal digits (a SHA-256), never "unknown". */
#include "rb_test.h"
#include "railbrake/rb_common.h"

#include <ctype.h>

int main(void)
{
    const char *hash = rb_build_hash();
    size_t n = strlen(hash), hex = 0;
    for (size_t i = 0; i < n; ++i) hex += isxdigit((unsigned char)hash[i]) && !isupper((unsigned char)hash[i]);
    CHECK(n == 64);
    CHECK(hex == n);
    CHECK(strcmp(hash, "unknown") != 0);
    return rb_test_summary("test_build_info");
}
