/* Reading a fuzzer's bytes as values: bytes run out into zeros, doubles come
 * from a table of awkward values (NaN, infinities, 0, -0, huge, tiny,
 * denormal), from raw bits, or as small decimals that make sensible scenes. */
#ifndef MPS2P_FUZZ_INPUT_H
#define MPS2P_FUZZ_INPUT_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct fuzz_input {
    const uint8_t *data;
    size_t left;
} fuzz_input;

static inline uint8_t take_u8(fuzz_input *in)
{
    if (!in->left)
        return 0;
    in->left--;
    return *in->data++;
}

static inline uint16_t take_u16(fuzz_input *in)
{
    uint16_t hi = take_u8(in);
    return (uint16_t)(hi << 8 | take_u8(in));
}

static inline double take_double(fuzz_input *in)
{
    static const double awkward[] = {
        0.0, -0.0, 1.0, -1.0, 0.01, 0.02, 0.05, 0.1, 0.5, 1e-3, 1e300, -1e300, 1e-300,
        4.9e-324, 1.7976931348623157e308, -1.7976931348623157e308, NAN, INFINITY, -INFINITY,
        2.1, 4.0, 0.97, 1000.0, 1e-6, 9.81, -9.81, 1e9, 3.0e9,
    };
    uint8_t how = take_u8(in);
    switch (how % 4) {
    case 0:
        return awkward[take_u8(in) % (sizeof awkward / sizeof awkward[0])];
    case 1: {
        uint8_t bytes[8] = {0};
        for (int i = 0; i < 8; i++)
            bytes[i] = take_u8(in);
        double value;
        memcpy(&value, bytes, sizeof value);
        return value;
    }
    case 2:
        return (int16_t)take_u16(in) / 100.0;
    default:
        return (int16_t)take_u16(in) / 1000.0;
    }
}

#endif
