/* Bounded smoke run of the frame-decoder fuzz target (fuzz_hil_frame.c): 30 000 mutated frames,
 * every accepted one re-encodes to its own bytes and holds the ICD's ranges (the target aborts
 * otherwise); `make fuzz` runs it far longer, with libFuzzer where clang is installed. */
#define RB_FUZZ_NO_MAIN
#include "fuzz_hil_frame.c"

#include "rb_test.h"

int main(void)
{
    long accepted = rb_hil_frame_fuzz_loop(30000, 7);
    printf("30000 mutated frames: %ld decoded\n", accepted);
    CHECK(accepted > 200);        /* the mutations reach the checks behind the CRC */
    CHECK(accepted < 30000);      /* ... and most are refused */
    return rb_test_summary("test_hil_frame_fuzz");
}
