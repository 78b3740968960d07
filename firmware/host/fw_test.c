/*
 * fw_test.c - host test driver of the polyforce firmware core (test/test_firmware.py runs it).
 *
 *   fw_test encode            stdin "seq t_us counts" lines -> "seq t_us counts HEX" (the encoded frame)
 *   fw_test edge SEED N       edge-case and N random frames, same output format
 *   fw_test seqwrap           pfw_seq_next from 0xFFFD, five steps
 *   fw_test be24              stdin "HEX6" lines -> "HEX6 counts" (24-bit two's complement)
 *   fw_test timediff          stdin "a b" lines -> "a b diff"
 *   fw_test golden            the golden messages (info, status, temperature), one hex line each
 *   fw_test message           stdin "type version HEXPAYLOAD|-" lines -> the encoded message in hex
 *   fw_test info              stdin "rate vref_uv gain bits mains adc board serial" ('-' = empty string)
 *                             lines -> the encoded info message in hex
 *   fw_test status            stdin "t_us reason wd_resets overflows reconfigs uptime" lines -> hex
 *   fw_test tempword          stdin "HEX4" lines (ADS1220 msb, mid) -> "HEX4 q5"
 *   fw_test divmod            stdin "n d" lines -> "n d quotient remainder" (pfw_divmod_u32)
 *   fw_test clock HZ BITS US0 stdin counter readings (first = at init) -> clock value after each,
 *                             or "invalid" when pfw_clock_init refuses the counter
 *   fw_test pacer RATE FIRST N the first N due times
 *   fw_test ring              fill / overflow / wrap / interleaving checks (exit status 0 = pass)
 *   fw_test threads N         the ring between two threads, N samples (exit status 0 = pass)
 *
 * Self-checks print "FAIL ..." and exit 1; success prints "ok ...".
 */
#define _POSIX_C_SOURCE 200809L
#include <inttypes.h>
#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../polyforce_fw.h"

static int failures = 0;

#define CHECK(cond)                                                                  \
    do {                                                                             \
        if (!(cond)) {                                                               \
            printf("FAIL %s:%d: %s\n", __FILE__, __LINE__, #cond);                   \
            failures++;                                                              \
        }                                                                            \
    } while (0)

static uint64_t rng_state = 0x9E3779B97F4A7C15u;

static uint64_t rng_next(void)
{ /* xorshift64* */
    rng_state ^= rng_state >> 12u;
    rng_state ^= rng_state << 25u;
    rng_state ^= rng_state >> 27u;
    return rng_state * 0x2545F4914F6CDD1Du;
}

static void print_frame(uint16_t seq, uint32_t t_us, int32_t counts)
{
    uint8_t frame[PFW_FRAME_SIZE];
    unsigned i;
    pfw_encode_frame(frame, seq, t_us, counts);
    printf("%u %" PRIu32 " %" PRId32 " ", (unsigned)seq, t_us, counts);
    for (i = 0u; i < PFW_FRAME_SIZE; ++i) {
        printf("%02x", (unsigned)frame[i]);
    }
    printf("\n");
}

static int cmd_encode(void)
{
    unsigned long seq, t_us;
    long counts;
    while (scanf("%lu %lu %ld", &seq, &t_us, &counts) == 3) {
        print_frame((uint16_t)seq, (uint32_t)t_us, (int32_t)counts);
    }
    return 0;
}

static int cmd_edge(unsigned long seed, unsigned long n)
{
    static const uint16_t seqs[] = {0u, 1u, 0x7FFFu, 0x8000u, 0xFFFEu, 0xFFFFu};
    static const uint32_t times[] = {0u, 1u, 999999u, 0x7FFFFFFFu, 0x80000000u, 0xFFFFFC17u, 0xFFFFFFFFu};
    static const int32_t counts[] = {0, 1, -1, 8388607, -8388608, INT32_MAX, INT32_MIN, INT32_MIN + 1, 0x5AA5, -0x5A5A5A5A};
    size_t i, j, k;
    unsigned long r;
    for (i = 0u; i < sizeof seqs / sizeof seqs[0]; ++i) {
        for (j = 0u; j < sizeof times / sizeof times[0]; ++j) {
            for (k = 0u; k < sizeof counts / sizeof counts[0]; ++k) {
                print_frame(seqs[i], times[j], counts[k]);
            }
        }
    }
    rng_state ^= (uint64_t)seed * 0x100000001B3u;
    for (r = 0u; r < n; ++r) {
        const uint64_t x = rng_next();
        const uint64_t y = rng_next();
        print_frame((uint16_t)(x & 0xFFFFu), (uint32_t)(x >> 32u), (int32_t)(uint32_t)(y >> 16u));
    }
    return 0;
}

static int cmd_seqwrap(void)
{
    uint16_t s = 0xFFFDu;
    int i;
    for (i = 0; i < 5; ++i) {
        printf("%u\n", (unsigned)s);
        s = pfw_seq_next(s);
    }
    return 0;
}

static int cmd_be24(void)
{
    unsigned long raw;
    while (scanf("%lx", &raw) == 1) {
        printf("%06lx %" PRId32 "\n", raw,
               pfw_counts_from_be24((uint8_t)(raw >> 16u), (uint8_t)(raw >> 8u), (uint8_t)raw));
    }
    return 0;
}

static int cmd_timediff(void)
{
    unsigned long a, b;
    while (scanf("%lu %lu", &a, &b) == 2) {
        printf("%lu %lu %" PRId32 "\n", a, b, pfw_time_diff_us((uint32_t)a, (uint32_t)b));
    }
    return 0;
}

static void print_hex(const uint8_t *data, size_t n)
{
    size_t i;
    for (i = 0u; i < n; ++i) {
        printf("%02x", (unsigned)data[i]);
    }
    printf("\n");
}

static int cmd_golden(void)
{
    uint8_t out[PFW_MSG_MAX_SIZE];
    pfw_info_t info;
    pfw_status_t status;
    memset(&info, 0, sizeof info);
    info.rate_hz = 1000u;
    info.vref_uv = 5000000u;
    info.gain = 128u;
    info.adc_bits = 24u;
    info.mains_filter = PFW_MAINS_OFF;
    strcpy(info.adc, "ADS1220");
    strcpy(info.board, "arduino-zero");
    strcpy(info.serial, "PF-2024-0001");
    print_hex(out, pfw_encode_info(out, &info));
    /* every field full, and 0xA5 bytes to stuff */
    info.rate_hz = 0xA5A5u;
    info.vref_uv = 0x5AA55AA5u;
    info.gain = 0xA55Au;
    info.adc_bits = 0xA5u;
    info.mains_filter = PFW_MAINS_50_60;
    memcpy(info.adc, "ABCDEFGH", PFW_INFO_ADC_LEN);
    memcpy(info.board, "0123456789abcdef", PFW_INFO_BOARD_LEN);
    memcpy(info.serial, "\xa5Z\xa5Z\xa5Z\xa5Z\xa5Z\xa5Z\xa5Z\xa5Z", PFW_INFO_SERIAL_LEN);
    print_hex(out, pfw_encode_info(out, &info));
    status.t_us = 0xA55A00A5u;
    status.reset_reason = PFW_RESET_WATCHDOG;
    status.watchdog_resets = 3u;
    status.overflows = 0x5A5Au;
    status.adc_reconfigs = 2u;
    status.uptime_s = 86400u;
    print_hex(out, pfw_encode_status(out, &status));
    print_hex(out, pfw_encode_temperature(out, 123456u, -813));
    return 0;
}

static int cmd_message(void)
{
    unsigned type, version;
    char hex[160];
    while (scanf("%u %u %150s", &type, &version, hex) == 3) {
        uint8_t payload[PFW_MSG_PAYLOAD_MAX + 2u];
        uint8_t out[PFW_MSG_MAX_SIZE];
        size_t len = 0u, n;
        if (strcmp(hex, "-") != 0) {
            while (hex[2u * len] != '\0' && len < sizeof payload) {
                unsigned byte;
                sscanf(&hex[2u * len], "%2x", &byte);
                payload[len++] = (uint8_t)byte;
            }
        }
        n = pfw_encode_message(out, (uint8_t)type, (uint8_t)version, payload, len);
        if (n == 0u) {
            printf("refused\n");
        } else {
            print_hex(out, n);
        }
    }
    return 0;
}

/* At most `size` chars of `text` ("-" = empty); a full field has no terminating NUL. */
static void copy_field(char *dst, const char *text, size_t size)
{
    size_t i;
    if (strcmp(text, "-") == 0) {
        return;
    }
    for (i = 0u; i < size && text[i] != '\0'; ++i) {
        dst[i] = text[i];
    }
}

static int cmd_info(void)
{
    unsigned long rate, vref;
    unsigned gain, bits, mains;
    char adc[64], board[64], serial[64];
    while (scanf("%lu %lu %u %u %u %63s %63s %63s", &rate, &vref, &gain, &bits, &mains, adc, board, serial) == 8) {
        pfw_info_t info;
        uint8_t out[PFW_MSG_MAX_SIZE];
        memset(&info, 0, sizeof info);
        info.rate_hz = (uint32_t)rate;
        info.vref_uv = (uint32_t)vref;
        info.gain = (uint16_t)gain;
        info.adc_bits = (uint8_t)bits;
        info.mains_filter = (uint8_t)mains;
        copy_field(info.adc, adc, PFW_INFO_ADC_LEN);
        copy_field(info.board, board, PFW_INFO_BOARD_LEN);
        copy_field(info.serial, serial, PFW_INFO_SERIAL_LEN);
        print_hex(out, pfw_encode_info(out, &info));
    }
    return 0;
}

static int cmd_status(void)
{
    unsigned long t_us, overflows, reconfigs, uptime;
    unsigned reason, wd;
    while (scanf("%lu %u %u %lu %lu %lu", &t_us, &reason, &wd, &overflows, &reconfigs, &uptime) == 6) {
        pfw_status_t status;
        uint8_t out[PFW_MSG_MAX_SIZE];
        status.t_us = (uint32_t)t_us;
        status.reset_reason = (uint8_t)reason;
        status.watchdog_resets = (uint16_t)wd;
        status.overflows = (uint32_t)overflows;
        status.adc_reconfigs = (uint32_t)reconfigs;
        status.uptime_s = (uint32_t)uptime;
        print_hex(out, pfw_encode_status(out, &status));
    }
    return 0;
}

static int cmd_tempword(void)
{
    unsigned long raw;
    while (scanf("%lx", &raw) == 1) {
        printf("%04lx %d\n", raw, (int)pfw_ads1220_temp_q5((uint8_t)(raw >> 8u), (uint8_t)raw));
    }
    return 0;
}

static int cmd_divmod(void)
{
    unsigned long n, d;
    while (scanf("%lu %lu", &n, &d) == 2) {
        uint32_t r = 0u;
        const uint32_t q = pfw_divmod_u32((uint32_t)n, (uint32_t)d, &r);
        printf("%lu %lu %" PRIu32 " %" PRIu32 "\n", n, d, q, r);
    }
    return 0;
}

static int cmd_clock(unsigned long hz, unsigned long bits, unsigned long us0)
{
    pfw_clock_t clock;
    unsigned long ticks;
    if (scanf("%lu", &ticks) != 1) {
        return 2;
    }
    if (pfw_clock_init(&clock, (uint32_t)hz, (uint32_t)bits, (uint32_t)ticks, (uint32_t)us0) != 0) {
        printf("invalid\n");
        return 0;
    }
    while (scanf("%lu", &ticks) == 1) {
        printf("%" PRIu32 "\n", pfw_clock_update(&clock, (uint32_t)ticks));
    }
    return 0;
}

static int cmd_pacer(unsigned long rate, unsigned long first, unsigned long n)
{
    pfw_pacer_t pacer;
    unsigned long i;
    if (pfw_pacer_init(&pacer, (uint32_t)rate, (uint32_t)first) != 0) {
        printf("invalid %" PRIu32 "\n", pfw_period_us((uint32_t)rate));
        return 0;
    }
    printf("period %" PRIu32 "\n", pfw_period_us((uint32_t)rate));
    for (i = 0u; i < n; ++i) {
        const uint32_t due = pacer.next_us;
        CHECK(pfw_pacer_due(&pacer, due));
        CHECK(!pfw_pacer_due(&pacer, due - 1u));
        CHECK(pfw_pacer_advance(&pacer) == due);
        printf("%" PRIu32 "\n", due);
    }
    return failures ? 1 : 0;
}

/* ---------------------------------------------------------------- ring checks */
static pfw_ring_t ring;

static void check_fill_and_overflow(void)
{
    pfw_sample_t s;
    uint32_t i;
    pfw_ring_init(&ring, 65530u);
    CHECK(pfw_ring_count(&ring) == 0u);
    CHECK(!pfw_ring_pop(&ring, &s));
    for (i = 0u; i < PFW_RING_CAPACITY; ++i) {
        CHECK(pfw_ring_record(&ring, 1000u * i, (int32_t)i - 7));
    }
    CHECK(pfw_ring_count(&ring) == PFW_RING_CAPACITY);
    CHECK(ring.overflows == 0u);
    /* full: refused and counted, nothing overwritten, but the sequence moves on */
    CHECK(!pfw_ring_record(&ring, 123u, 999));
    CHECK(!pfw_ring_record(&ring, 124u, 998));
    CHECK(ring.overflows == 2u);
    CHECK(pfw_ring_count(&ring) == PFW_RING_CAPACITY);
    for (i = 0u; i < PFW_RING_CAPACITY; ++i) {
        CHECK(pfw_ring_pop(&ring, &s));
        CHECK(s.counts == (int32_t)i - 7);
        CHECK(s.t_us == 1000u * i);
        CHECK(s.seq == (uint16_t)((65530u + i) & 0xFFFFu)); /* wraps through 0 */
    }
    CHECK(!pfw_ring_pop(&ring, &s));
    /* the next sample carries the sequence number after the two refused ones: a gap of 2 */
    CHECK(pfw_ring_record(&ring, 5u, 5));
    CHECK(pfw_ring_pop(&ring, &s));
    CHECK(s.seq == (uint16_t)((65530u + PFW_RING_CAPACITY + 2u) & 0xFFFFu));
    printf("ok fill capacity=%u overflows=%" PRIu32 "\n", (unsigned)PFW_RING_CAPACITY, ring.overflows);
}

static void check_wrap_interleaved(void)
{
    /* many passes over the slots and, for narrow index types, over the index range itself */
    pfw_sample_t s;
    uint32_t pushed = 0u, popped = 0u, round;
    uint8_t frame[PFW_FRAME_SIZE];
    pfw_ring_init(&ring, 0u);
    for (round = 0u; round < 5000u; ++round) {
        const uint32_t n_push = (round * 7u + 3u) % (PFW_RING_CAPACITY + 1u);
        uint32_t n_pop = (round * 13u + 5u) % (PFW_RING_CAPACITY + 1u);
        uint32_t k;
        for (k = 0u; k < n_push; ++k) {
            if (pfw_ring_count(&ring) < PFW_RING_CAPACITY) {
                CHECK(pfw_ring_record(&ring, pushed, -(int32_t)pushed));
                pushed++;
            }
        }
        CHECK(pfw_ring_count(&ring) == pushed - popped);
        while ((n_pop > 0u) && pfw_ring_pop(&ring, &s)) {
            CHECK(s.t_us == popped);
            CHECK(s.counts == -(int32_t)popped);
            CHECK(s.seq == (uint16_t)(popped & 0xFFFFu));
            popped++;
            n_pop--;
        }
    }
    while (pfw_ring_pop_frame(&ring, frame)) {
        uint8_t expect[PFW_FRAME_SIZE];
        pfw_encode_frame(expect, (uint16_t)(popped & 0xFFFFu), popped, -(int32_t)popped);
        CHECK(memcmp(frame, expect, sizeof frame) == 0);
        popped++;
    }
    CHECK(popped == pushed);
    CHECK(ring.overflows == 0u);
    CHECK(pushed > 100u * PFW_RING_CAPACITY);
    printf("ok wrap pushed=%" PRIu32 " index_bytes=%u\n", pushed, (unsigned)sizeof(pfw_index_t));
}

static int cmd_ring(void)
{
    check_fill_and_overflow();
    check_wrap_interleaved();
    return failures ? 1 : 0;
}

/* ---------------------------------------------------------------- two threads */
static uint32_t thread_n;
static volatile int producer_done = 0;

static void *producer(void *arg)
{
    uint32_t i;
    (void)arg;
    for (i = 0u; i < thread_n; ++i) {
        /* first half: wait while full (lossless hand-over); second half: free-running (overflows) */
        while ((i < thread_n / 2u) && (pfw_ring_count(&ring) >= PFW_RING_CAPACITY)) {
            (void)sched_yield(); /* a shared or single core must let the consumer run */
        }
        (void)pfw_ring_record(&ring, i, (int32_t)(i * 3u));
    }
    __atomic_store_n(&producer_done, 1, __ATOMIC_SEQ_CST);
    return NULL;
}

static int cmd_threads(unsigned long n)
{
    pthread_t tid;
    pfw_sample_t s;
    uint32_t received = 0u, gaps = 0u, expect_t = 0u;
    thread_n = (uint32_t)n;
    pfw_ring_init(&ring, 0u);
    if (pthread_create(&tid, NULL, producer, NULL) != 0) {
        printf("FAIL pthread_create\n");
        return 1;
    }
    for (;;) {
        if (pfw_ring_pop(&ring, &s)) {
            /* every sample arrives intact and in order; refused ones leave a gap in t and seq alike */
            CHECK(s.t_us >= expect_t);
            CHECK(s.counts == (int32_t)(s.t_us * 3u));
            CHECK(s.seq == (uint16_t)(s.t_us & 0xFFFFu));
            gaps += s.t_us - expect_t;
            expect_t = s.t_us + 1u;
            received++;
            if (failures > 10) {
                break;
            }
        } else if (__atomic_load_n(&producer_done, __ATOMIC_SEQ_CST) && pfw_ring_count(&ring) == 0u) {
            break;
        } else {
            (void)sched_yield();
        }
    }
    pthread_join(tid, NULL);
    gaps += thread_n - expect_t;
    CHECK(received + gaps == thread_n);
    CHECK(gaps == ring.overflows);
    CHECK(received >= thread_n / 2u);
    printf("ok threads received=%" PRIu32 " overflows=%" PRIu32 "\n", received, ring.overflows);
    return failures ? 1 : 0;
}

int main(int argc, char **argv)
{
    const char *cmd = (argc > 1) ? argv[1] : "";
    if (strcmp(cmd, "encode") == 0) {
        return cmd_encode();
    }
    if (strcmp(cmd, "edge") == 0 && argc == 4) {
        return cmd_edge(strtoul(argv[2], NULL, 0), strtoul(argv[3], NULL, 0));
    }
    if (strcmp(cmd, "seqwrap") == 0) {
        return cmd_seqwrap();
    }
    if (strcmp(cmd, "be24") == 0) {
        return cmd_be24();
    }
    if (strcmp(cmd, "timediff") == 0) {
        return cmd_timediff();
    }
    if (strcmp(cmd, "golden") == 0) {
        return cmd_golden();
    }
    if (strcmp(cmd, "message") == 0) {
        return cmd_message();
    }
    if (strcmp(cmd, "info") == 0) {
        return cmd_info();
    }
    if (strcmp(cmd, "status") == 0) {
        return cmd_status();
    }
    if (strcmp(cmd, "tempword") == 0) {
        return cmd_tempword();
    }
    if (strcmp(cmd, "divmod") == 0) {
        return cmd_divmod();
    }
    if (strcmp(cmd, "clock") == 0 && argc == 5) {
        return cmd_clock(strtoul(argv[2], NULL, 0), strtoul(argv[3], NULL, 0), strtoul(argv[4], NULL, 0));
    }
    if (strcmp(cmd, "pacer") == 0 && argc == 5) {
        return cmd_pacer(strtoul(argv[2], NULL, 0), strtoul(argv[3], NULL, 0), strtoul(argv[4], NULL, 0));
    }
    if (strcmp(cmd, "ring") == 0) {
        return cmd_ring();
    }
    if (strcmp(cmd, "threads") == 0 && argc == 3) {
        return cmd_threads(strtoul(argv[2], NULL, 0));
    }
    fprintf(stderr, "usage: fw_test encode|edge SEED N|golden|message|info|status|tempword|seqwrap|be24|timediff|divmod|clock HZ BITS US0|pacer RATE FIRST N|ring|threads N\n");
    return 2;
}
