/* Build-time tool: writes the estimator's sorting networks header.
 *
 *   gen_sorting_networks OUT.h
 *
 * Batcher's merge-exchange networks (Knuth, TAOCP vol. 3, 5.2.2, Algorithm
 * M) for n = 1..64, each checked before anything is written: by the 0-1
 * principle (all 2^n inputs of zeros and ones) for n <= FULL_CHECK_MAX, on
 * random inputs beyond. Exits 1 without writing if a network fails, or if
 * the checks pass a network that does not sort. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#define MAX_N 64
/* The 0-1 check of n = 24 takes a fraction of a second; each n more doubles it. */
#define FULL_CHECK_MAX 24
#define RANDOM_TRIALS 2000
#define MAX_COMPARATORS 543 /* the network for n = 64 */

typedef struct {
    int count;
    unsigned char pairs[MAX_COMPARATORS][2]; /* (i, j), i < j: afterwards v[i] <= v[j] */
} Network;

/* Algorithm M: comparators in the order the algorithm visits them. */
static void merge_exchange(int n, Network *network)
{
    network->count = 0;
    if (n < 2)
        return;
    int t = 0;
    while ((1 << t) < n)
        ++t;
    for (int p = 1 << (t - 1); p > 0; p >>= 1) {
        int q = 1 << (t - 1), r = 0, d = p;
        for (;;) {
            for (int i = 0; i < n - d; ++i)
                if ((i & p) == r) {
                    if (network->count == MAX_COMPARATORS) {
                        fprintf(stderr, "gen_sorting_networks: n = %d needs over %d comparators\n", n, MAX_COMPARATORS);
                        exit(1);
                    }
                    network->pairs[network->count][0] = (unsigned char)i;
                    network->pairs[network->count][1] = (unsigned char)(i + d);
                    ++network->count;
                }
            if (q == p)
                break;
            d = q - p;
            q >>= 1;
            r = p;
        }
    }
}

/* The 0-1 principle, bit-parallel: the 2^n inputs in blocks of 64, word
 * column[i] holding element i of the block's 64 inputs (input number k has
 * element i = bit i of k). Sorted: no 1 before a 0 in any input. */
static int sorts_all_zero_one(int n, const Network *network)
{
    static const uint64_t low_bits[6] = {0xaaaaaaaaaaaaaaaaull, 0xccccccccccccccccull, 0xf0f0f0f0f0f0f0f0ull,
                                         0xff00ff00ff00ff00ull, 0xffff0000ffff0000ull, 0xffffffff00000000ull};
    uint64_t blocks = n > 6 ? 1ull << (n - 6) : 1;
    uint64_t valid = n >= 6 ? ~0ull : (1ull << (1u << n)) - 1;
    for (uint64_t block = 0; block < blocks; ++block) {
        uint64_t column[MAX_N];
        for (int i = 0; i < n; ++i)
            column[i] = i < 6 ? low_bits[i] : (block >> (i - 6) & 1) ? ~0ull : 0;
        for (int k = 0; k < network->count; ++k) {
            int i = network->pairs[k][0], j = network->pairs[k][1];
            uint64_t low = column[i] & column[j], high = column[i] | column[j];
            column[i] = low;
            column[j] = high;
        }
        for (int i = 0; i + 1 < n; ++i)
            if (column[i] & ~column[i + 1] & valid)
                return 0;
    }
    return 1;
}

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Random inputs with repeated values (drawn from 0..4n-1): the output must
 * be ascending and hold the input's values (counted per value). */
static int sorts_random(int n, const Network *network)
{
    uint64_t state = (uint64_t)n;
    for (int trial = 0; trial < RANDOM_TRIALS; ++trial) {
        int v[MAX_N], histogram[4 * MAX_N] = {0};
        for (int i = 0; i < n; ++i) {
            v[i] = (int)(splitmix64(&state) % (uint64_t)(4 * n));
            ++histogram[v[i]];
        }
        for (int k = 0; k < network->count; ++k) {
            int i = network->pairs[k][0], j = network->pairs[k][1];
            if (v[i] > v[j]) {
                int swap = v[i];
                v[i] = v[j];
                v[j] = swap;
            }
        }
        for (int i = 0; i < n; ++i)
            if (--histogram[v[i]] < 0 || (i > 0 && v[i - 1] > v[i]))
                return 0;
    }
    return 1;
}

static int network_valid(int n, const Network *network)
{
    for (int k = 0; k < network->count; ++k)
        if (network->pairs[k][0] >= network->pairs[k][1] || network->pairs[k][1] >= n)
            return 0;
    return n <= FULL_CHECK_MAX ? sorts_all_zero_one(n, network) : sorts_random(n, network);
}

/* A check that cannot fail proves nothing: each method must reject a
 * network without its last comparator. */
static int checks_reject_a_broken_network(void)
{
    static const int sizes[] = {FULL_CHECK_MAX, MAX_N};
    for (int s = 0; s < 2; ++s) {
        static Network broken;
        merge_exchange(sizes[s], &broken);
        --broken.count;
        if (network_valid(sizes[s], &broken))
            return 0;
    }
    return 1;
}

/* Macro bodies: per_line items to a line, continued with backslashes. */
static void put_separator(FILE *out, int item, int per_line, int commas)
{
    if (item == 0)
        fputs("    ", out);
    else
        fprintf(out, "%s%s", commas ? "," : "", item % per_line ? " " : " \\\n    ");
}

static void write_header(FILE *out, const Network *networks)
{
    fputs("/* Sorting networks for the estimator: Batcher's merge-exchange networks\n"
          " * (Knuth, TAOCP vol. 3, 5.2.2, Algorithm M) for n = 1..64.\n"
          " *\n"
          " * GENERATED by host/tools/gen_sorting_networks.c at build time; do not\n"
          " * edit. EST_NETWORK_<n>(CE) expands to CE(i, j) for each\n"
          " * comparator in order (i < j: afterwards v[i] <= v[j]). EST_NETWORK_START\n"
          " * lists 65 offsets into EST_ALL_NETWORKS (the networks for n = 1, 2, ...,\n"
          " * 64 laid end to end): network n is comparators EST_NETWORK_START[n - 1]\n"
          " * .. EST_NETWORK_START[n] - 1. Valid C11 and OpenCL C. */\n"
          "#ifndef KERNELS_SORTING_NETWORKS_H\n"
          "#define KERNELS_SORTING_NETWORKS_H\n\n",
          out);
    int start[MAX_N + 1], total = 0;
    for (int n = 1; n <= MAX_N; ++n) {
        const Network *network = &networks[n - 1];
        start[n - 1] = total;
        total += network->count;
        fprintf(out, "/* n = %d: %d comparators */\n#define EST_NETWORK_%d(CE)%s\n", n, network->count, n,
                network->count ? " \\" : "");
        for (int k = 0; k < network->count; ++k) {
            put_separator(out, k, 10, 0);
            fprintf(out, "CE(%d, %d)", network->pairs[k][0], network->pairs[k][1]);
        }
        if (network->count)
            fputs("\n", out);
    }
    start[MAX_N] = total;
    fprintf(out, "\n/* All 64 networks end to end: %d comparators. */\n#define EST_ALL_NETWORKS(CE) \\\n", total);
    for (int n = 1; n <= MAX_N; ++n) {
        put_separator(out, n - 1, 8, 0);
        fprintf(out, "EST_NETWORK_%d(CE)", n);
    }
    fputs("\n#define EST_NETWORK_START \\\n", out);
    for (int n = 0; n <= MAX_N; ++n) {
        put_separator(out, n, 13, 1);
        fprintf(out, "%d", start[n]);
    }
    fputs("\n\n#endif /* KERNELS_SORTING_NETWORKS_H */\n", out);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: gen_sorting_networks OUT.h\n");
        return 2;
    }
    if (!checks_reject_a_broken_network()) {
        fprintf(stderr, "gen_sorting_networks: the checks pass a network that does not sort\n");
        return 1;
    }
    static Network networks[MAX_N];
    for (int n = 1; n <= MAX_N; ++n) {
        merge_exchange(n, &networks[n - 1]);
        if (!network_valid(n, &networks[n - 1])) {
            fprintf(stderr, "gen_sorting_networks: the network for n = %d does not sort\n", n);
            return 1;
        }
    }
    FILE *out = fopen(argv[1], "w");
    if (!out) {
        fprintf(stderr, "gen_sorting_networks: cannot write %s\n", argv[1]);
        return 1;
    }
    write_header(out, networks);
    if (fclose(out) != 0) {
        fprintf(stderr, "gen_sorting_networks: cannot write %s\n", argv[1]);
        remove(argv[1]);
        return 1;
    }
    return 0;
}
