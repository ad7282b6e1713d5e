#include "exact_sum.h"

#include <math.h>
#include <string.h>

#define UNIT_EXPONENT (-160)

void exact_sum_add(ExactSum *sum, float x)
{
    uint32_t bits;
    memcpy(&bits, &x, sizeof bits);
    int biased = (int)((bits >> 23) & 0xff);
    uint64_t significand = bits & 0x7fffff;
    if (biased != 0)
        significand |= 0x800000;
    int shift = (biased != 0 ? biased : 1) - 150 - UNIT_EXPONENT; /* >= 11 */
    /* significand << shift, word by word, as a 384-bit addend (negated for
     * a negative x: the two's complement of the magnitude). */
    uint32_t addend[EXACT_SUM_WORDS] = {0};
    int word = shift / 32, offset = shift % 32;
    uint64_t wide = significand << offset; /* at most 24 + 31 bits */
    for (int i = 0; i < 3 && word + i < EXACT_SUM_WORDS; ++i)
        addend[word + i] = (uint32_t)(wide >> (32 * i));
    if (bits >> 31) {
        uint64_t carry = 1;
        for (int i = 0; i < EXACT_SUM_WORDS; ++i) {
            uint64_t v = (uint64_t)(uint32_t)~addend[i] + carry;
            addend[i] = (uint32_t)v;
            carry = v >> 32;
        }
    }
    uint64_t carry = 0;
    for (int i = 0; i < EXACT_SUM_WORDS; ++i) {
        uint64_t v = (uint64_t)sum->words[i] + addend[i] + carry;
        sum->words[i] = (uint32_t)v;
        carry = v >> 32;
    }
}

long double exact_sum_to_long_double(const ExactSum *sum)
{
    uint32_t magnitude[EXACT_SUM_WORDS];
    memcpy(magnitude, sum->words, sizeof magnitude);
    int negative = (int)(magnitude[EXACT_SUM_WORDS - 1] >> 31);
    if (negative) {
        uint64_t carry = 1;
        for (int i = 0; i < EXACT_SUM_WORDS; ++i) {
            uint64_t v = (uint64_t)(uint32_t)~magnitude[i] + carry;
            magnitude[i] = (uint32_t)v;
            carry = v >> 32;
        }
    }
    int top = -1; /* index of the highest set bit */
    for (int i = EXACT_SUM_WORDS * 32 - 1; i >= 0 && top < 0; --i)
        if ((magnitude[i / 32] >> (i % 32)) & 1)
            top = i;
    if (top < 0)
        return 0.0L;
    /* The 64 bits from the top one, the lowest made sticky for every bit
     * below them: exact in a long double, which then rounds to float once
     * (the sticky bit lies far below the float's last bit). */
    int low = top >= 63 ? top - 63 : 0;
    uint64_t window = 0;
    int sticky = 0;
    for (int i = 0; i < EXACT_SUM_WORDS * 32; ++i) {
        int bit = (int)((magnitude[i / 32] >> (i % 32)) & 1);
        if (i < low)
            sticky |= bit;
        else if (i <= top)
            window |= (uint64_t)bit << (i - low);
    }
    window |= (uint64_t)sticky;
    long double value = ldexpl((long double)window, low + UNIT_EXPONENT);
    return negative ? -value : value;
}

float exact_sum_to_float(const ExactSum *sum)
{
    return (float)exact_sum_to_long_double(sum);
}

long double test_set_sum(const uint64_t *accumulators, uint32_t set, uint32_t channel, size_t pixel, size_t pixel_count)
{
    /* Layout: the grid plane (0 or E + 1024), then [set][channel][word]. */
    uint64_t grid = accumulators[pixel];
    size_t lo_plane = 1 + ((size_t)set * 3 + channel) * 2;
    uint64_t lo = accumulators[lo_plane * pixel_count + pixel], hi = accumulators[(lo_plane + 1) * pixel_count + pixel];
    int negative = (int)(hi >> 63);
    if (negative) {
        lo = ~lo + 1;
        hi = ~hi + (lo == 0);
    }
    long double units = ldexpl((long double)hi, 64) + (long double)lo;
    return ldexpl(negative ? -units : units, grid == 0 ? 0 : (int)grid - 1024);
}
