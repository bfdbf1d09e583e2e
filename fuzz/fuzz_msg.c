/* fuzz_msg: libFuzzer target for one message type (built once per type
 * with -DFUZZ_TYPE=tandem_<name>_t by tools/fuzz.sh).
 *
 * Drives the receive path every daemon uses: the raw-byte wire check
 * (src/daemons/common/wire.c), then, only for bytes it accepted, lcm-gen's
 * decoder, the shared validators, re-encoding and cleanup. Fails (abort)
 * when the checker accepts bytes that lcm-gen cannot decode or that do not
 * encode back to the same bytes (the two disagree about the layout); the
 * sanitizers catch crashes, overflows and leaks.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "msg_check.h"
#include "wire.h"
#include "tandem_wire_types.h"

#define CAT3(a, b, c) a##b##c
#define XCAT3(a, b, c) CAT3(a, b, c)
#define WIRE_T XCAT3(wire_t_, FUZZ_TYPE, )
#define DECODE XCAT3(FUZZ_TYPE, _decode, )
#define ENCODE XCAT3(FUZZ_TYPE, _encode, )
#define CLEANUP XCAT3(FUZZ_TYPE, _decode_cleanup, )
#include FUZZ_HEADER /* "tandem_<name>_t.h", from tools/fuzz.sh */

/* The validators tandem-arm applies to the types that can move an arm. */
static void validate(const void *m)
{
#if defined(FUZZ_ACTION_ROW)
    (void)action_row_check((const tandem_action_row_t *)m, 1, 8);
#elif defined(FUZZ_JOINT_REF)
    static const double q[ARM_NJ] = { 0 };
    (void)joint_ref_check((const tandem_arm_joint_ref_t *)m, 1, &arm_model_puma560, q, 1000, 20);
#else
    (void)m;
#endif
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    FUZZ_TYPE m;
    static uint8_t again[1 << 20];
    int n;
    (void)wire_find(data, size);
    (void)wire_seq(data, size);
    if (wire_check(&WIRE_T, data, size) != WIRE_OK || size > sizeof again)
        return 0; /* what every daemon drops before decoding */
    memset(&m, 0, sizeof m);
    if (DECODE(data, 0, (int)size, &m) != (int)size)
        abort(); /* accepted by the checker, refused by lcm-gen */
    validate(&m);
    n = ENCODE(again, 0, (int)sizeof again, &m);
    if (n != (int)size || memcmp(again, data, size) != 0)
        abort(); /* the two disagree about the layout */
    CLEANUP(&m);
    return 0;
}
