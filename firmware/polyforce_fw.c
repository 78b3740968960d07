/*
 * polyforce_fw.c - portable core of the polyforce bridge-ADC firmware (C99).
 * See polyforce_fw.h for the frame format and the concurrency rules.
 */
#include "polyforce_fw.h"

#define PFW_US_PER_S 1000000u
#define PFW_TWO_POW_24 16777216 /* fits int32_t */

/* ------------------------------------------------------------------ frame */
uint16_t pfw_crc16_ccitt(const uint8_t *data, size_t len, uint16_t crc)
{
    uint32_t c = crc; /* 32-bit intermediate: no shift ever reaches a signed int */
    size_t i;
    for (i = 0u; i < len; ++i) {
        uint32_t bit;
        c ^= ((uint32_t)data[i] << 8u);
        for (bit = 0u; bit < 8u; ++bit) {
            if ((c & 0x8000u) != 0u) {
                c = ((c << 1u) ^ 0x1021u) & 0xFFFFu;
            } else {
                c = (c << 1u) & 0xFFFFu;
            }
        }
    }
    return (uint16_t)c;
}

static void put_u16(uint8_t *dst, uint16_t v)
{
    dst[0] = (uint8_t)(v & 0xFFu);
    dst[1] = (uint8_t)((uint32_t)v >> 8u);
}

static void put_u32(uint8_t *dst, uint32_t v)
{
    dst[0] = (uint8_t)(v & 0xFFu);
    dst[1] = (uint8_t)((v >> 8u) & 0xFFu);
    dst[2] = (uint8_t)((v >> 16u) & 0xFFu);
    dst[3] = (uint8_t)((v >> 24u) & 0xFFu);
}

void pfw_encode_frame(uint8_t out[PFW_FRAME_SIZE], uint16_t seq, uint32_t t_us, int32_t counts)
{
    out[0] = (uint8_t)PFW_SYNC0;
    out[1] = (uint8_t)PFW_SYNC1;
    put_u16(&out[2], seq);
    put_u32(&out[4], t_us);
    /* int32 -> uint32 is defined (modulo 2^32): the two's complement bit pattern on every target */
    put_u32(&out[8], (uint32_t)counts);
    put_u16(&out[12], pfw_crc16_ccitt(&out[2], 10u, (uint16_t)PFW_CRC_INIT));
}

uint16_t pfw_seq_next(uint16_t seq)
{
    return (uint16_t)(((uint32_t)seq + 1u) & 0xFFFFu);
}

int32_t pfw_time_diff_us(uint32_t a, uint32_t b)
{
    const uint32_t d = a - b; /* modulo 2^32 */
    int32_t result;
    if (d <= (uint32_t)INT32_MAX) {
        result = (int32_t)d;
    } else {
        /* d - 2^32, written as -(2^32 - 1 - d) - 1 so that every value stays in int32 range */
        result = -(int32_t)(~d) - 1;
    }
    return result;
}

int32_t pfw_counts_from_be24(uint8_t msb, uint8_t mid, uint8_t lsb)
{
    const uint32_t raw = ((uint32_t)msb << 16u) | ((uint32_t)mid << 8u) | (uint32_t)lsb;
    int32_t value = (int32_t)raw; /* raw < 2^24: exact */
    if ((raw & 0x800000u) != 0u) {
        value -= (int32_t)PFW_TWO_POW_24; /* sign bit set: value - 2^24, in [-2^23, -1] */
    }
    return value;
}

/* --------------------------------------------------------------- messages */
#define PFW_MSG_HEADER 4u /* type, version, len, ~len */

static size_t put_stuffed(uint8_t *out, size_t n, uint8_t byte)
{
    out[n] = byte;
    n++;
    if (byte == (uint8_t)PFW_SYNC0) {
        out[n] = (uint8_t)PFW_MSG_STUFF; /* 0xA5 is always followed by 0x00: never 0xA5 0x5A */
        n++;
    }
    return n;
}

size_t pfw_encode_message(uint8_t *out, uint8_t type, uint8_t version, const uint8_t *payload, size_t len)
{
    uint8_t header[PFW_MSG_HEADER];
    uint16_t crc;
    size_t n = 0u;
    size_t i;
    if (len > PFW_MSG_PAYLOAD_MAX) {
        return 0u;
    }
    header[0] = type;
    header[1] = version;
    header[2] = (uint8_t)len;
    header[3] = (uint8_t)(~(uint32_t)len & 0xFFu);
    crc = pfw_crc16_ccitt(header, PFW_MSG_HEADER, (uint16_t)PFW_CRC_INIT);
    crc = pfw_crc16_ccitt(payload, len, crc);
    out[0] = (uint8_t)PFW_SYNC0;
    out[1] = (uint8_t)PFW_MSG_SYNC1;
    n = 2u;
    for (i = 0u; i < PFW_MSG_HEADER; ++i) {
        n = put_stuffed(out, n, header[i]);
    }
    for (i = 0u; i < len; ++i) {
        n = put_stuffed(out, n, payload[i]);
    }
    n = put_stuffed(out, n, (uint8_t)(crc & 0xFFu));
    n = put_stuffed(out, n, (uint8_t)((uint32_t)crc >> 8u));
    return n;
}

/* Copies a string of at most `size` chars into dst, padding with NUL (no library call). */
static void put_text(uint8_t *dst, const char *text, size_t size)
{
    size_t i;
    bool ended = false;
    for (i = 0u; i < size; ++i) {
        if (!ended && (text[i] == '\0')) {
            ended = true;
        }
        dst[i] = ended ? 0u : (uint8_t)(unsigned char)text[i];
    }
}

size_t pfw_encode_info(uint8_t *out, const pfw_info_t *info)
{
    uint8_t p[16u + PFW_INFO_ADC_LEN + PFW_INFO_BOARD_LEN + PFW_INFO_SERIAL_LEN];
    p[0] = (uint8_t)PFW_PROTOCOL_VERSION;
    p[1] = (uint8_t)PFW_FW_VERSION_MAJOR;
    p[2] = (uint8_t)PFW_FW_VERSION_MINOR;
    p[3] = (uint8_t)PFW_FW_VERSION_PATCH;
    put_u32(&p[4], info->rate_hz);
    put_u32(&p[8], info->vref_uv);
    put_u16(&p[12], info->gain);
    p[14] = info->adc_bits;
    p[15] = info->mains_filter;
    put_text(&p[16], info->adc, PFW_INFO_ADC_LEN);
    put_text(&p[16u + PFW_INFO_ADC_LEN], info->board, PFW_INFO_BOARD_LEN);
    put_text(&p[16u + PFW_INFO_ADC_LEN + PFW_INFO_BOARD_LEN], info->serial, PFW_INFO_SERIAL_LEN);
    return pfw_encode_message(out, (uint8_t)PFW_MSG_INFO, 1u, p, sizeof p);
}

size_t pfw_encode_status(uint8_t *out, const pfw_status_t *status)
{
    uint8_t p[20];
    put_u32(&p[0], status->t_us);
    p[4] = status->reset_reason;
    p[5] = 0u; /* reserved */
    put_u16(&p[6], status->watchdog_resets);
    put_u32(&p[8], status->overflows);
    put_u32(&p[12], status->adc_reconfigs);
    put_u32(&p[16], status->uptime_s);
    return pfw_encode_message(out, (uint8_t)PFW_MSG_STATUS, 1u, p, sizeof p);
}

size_t pfw_encode_temperature(uint8_t *out, uint32_t t_us, int16_t temp_q5)
{
    uint8_t p[6];
    put_u32(&p[0], t_us);
    /* int16 -> uint16 is defined (modulo 2^16): the two's complement bit pattern */
    put_u16(&p[4], (uint16_t)temp_q5);
    return pfw_encode_message(out, (uint8_t)PFW_MSG_TEMPERATURE, 1u, p, sizeof p);
}

int16_t pfw_ads1220_temp_q5(uint8_t msb, uint8_t mid)
{
    const uint32_t raw = ((uint32_t)msb << 6u) | ((uint32_t)mid >> 2u); /* 14 bits */
    int32_t value = (int32_t)raw;
    if ((raw & 0x2000u) != 0u) {
        value -= 16384; /* sign bit set: value - 2^14, in [-8192, -1] */
    }
    return (int16_t)value;
}

/* ------------------------------------------------------------------ ring */
#define PFW_RING_MASK ((uint32_t)PFW_RING_CAPACITY - 1u)

void pfw_ring_init(pfw_ring_t *ring, uint16_t first_seq)
{
    ring->head = 0u;
    ring->tail = 0u;
    ring->overflows = 0u;
    ring->next_seq = first_seq;
}

static uint32_t ring_used(pfw_index_t head, pfw_index_t tail)
{
    /* free-running indices: the difference modulo the index range is the fill level */
    return (uint32_t)(pfw_index_t)(head - tail);
}

bool pfw_ring_push(pfw_ring_t *ring, const pfw_sample_t *sample)
{
    const pfw_index_t head = ring->head; /* own index: no race */
    const pfw_index_t tail = ring->tail; /* the consumer's index: one volatile load */
    bool stored = false;
    PFW_BARRIER(); /* acquire: the consumer has finished reading every slot before `tail` */
    if (ring_used(head, tail) >= (uint32_t)PFW_RING_CAPACITY) {
        ring->overflows = ring->overflows + 1u; /* never overwrite unread data */
    } else {
        ring->slot[(uint32_t)head & PFW_RING_MASK] = *sample;
        PFW_BARRIER(); /* release: the slot is complete before the consumer can see it */
        ring->head = (pfw_index_t)(head + 1u);
        stored = true;
    }
    return stored;
}

bool pfw_ring_record(pfw_ring_t *ring, uint32_t t_us, int32_t counts)
{
    pfw_sample_t sample;
    sample.t_us = t_us;
    sample.counts = counts;
    sample.seq = ring->next_seq;
    ring->next_seq = pfw_seq_next(ring->next_seq);
    return pfw_ring_push(ring, &sample);
}

bool pfw_ring_pop(pfw_ring_t *ring, pfw_sample_t *out)
{
    const pfw_index_t tail = ring->tail; /* own index */
    const pfw_index_t head = ring->head; /* the producer's index: one volatile load */
    bool taken = false;
    PFW_BARRIER(); /* acquire: the slots before `head` are complete */
    if (head != tail) {
        *out = ring->slot[(uint32_t)tail & PFW_RING_MASK];
        PFW_BARRIER(); /* release: the slot is read before the producer may refill it */
        ring->tail = (pfw_index_t)(tail + 1u);
        taken = true;
    }
    return taken;
}

bool pfw_ring_pop_frame(pfw_ring_t *ring, uint8_t out[PFW_FRAME_SIZE])
{
    pfw_sample_t sample;
    const bool taken = pfw_ring_pop(ring, &sample);
    if (taken) {
        pfw_encode_frame(out, sample.seq, sample.t_us, sample.counts);
    }
    return taken;
}

uint32_t pfw_ring_count(const pfw_ring_t *ring)
{
    const pfw_index_t tail = ring->tail;
    const pfw_index_t head = ring->head;
    return ring_used(head, tail);
}

/* ------------------------------------------------------------------ division */
uint32_t pfw_divmod_u32(uint32_t n, uint32_t d, uint32_t *rem)
{
#if PFW_SOFT_DIVIDE
    /* restoring division, one quotient bit per step; `carry` holds the 33rd bit of r << 1 */
    uint32_t q = 0u;
    uint32_t r = 0u;
    uint32_t bit = 32u;
    while (bit > 0u) {
        uint32_t carry;
        bit--;
        carry = r >> 31u;
        r = (r << 1u) | ((n >> bit) & 1u);
        if ((carry != 0u) || (r >= d)) {
            r -= d; /* modulo 2^32: exact, the true value r + carry * 2^32 is >= d */
            q |= ((uint32_t)1u << bit);
        }
    }
    *rem = r;
    return q;
#else
    *rem = n % d;
    return n / d;
#endif
}

/* ------------------------------------------------------------------ clock */
static uint32_t gcd_u32(uint32_t a, uint32_t b)
{
    while (b != 0u) {
        uint32_t r;
        (void)pfw_divmod_u32(a, b, &r);
        a = b;
        b = r;
    }
    return a;
}

int pfw_clock_init(pfw_clock_t *clock, uint32_t tick_hz, uint32_t counter_bits, uint32_t ticks_now, uint32_t us_start)
{
    int status = -1;
    if ((tick_hz != 0u) && (counter_bits >= 1u) && (counter_bits <= 32u)) {
        uint32_t unused;
        const uint32_t g = gcd_u32(PFW_US_PER_S, tick_hz);
        const uint32_t num = pfw_divmod_u32(PFW_US_PER_S, g, &unused);
        const uint32_t den = pfw_divmod_u32(tick_hz, g, &unused);
        /* rem + r * num with rem, r <= den - 1 must fit in 32 bits; num + 1 <= 1e6 + 1 */
        if ((den - 1u) <= pfw_divmod_u32(0xFFFFFFFFu, num + 1u, &unused)) {
            clock->num = num;
            clock->den = den;
            clock->mask = (counter_bits == 32u) ? 0xFFFFFFFFu : (((uint32_t)1u << counter_bits) - 1u);
            clock->last_ticks = ticks_now & clock->mask;
            clock->rem = 0u;
            clock->us = us_start;
            status = 0;
        }
    }
    return status;
}

uint32_t pfw_clock_update(pfw_clock_t *clock, uint32_t ticks_now)
{
    const uint32_t now = ticks_now & clock->mask;
    const uint32_t delta = (now - clock->last_ticks) & clock->mask; /* one counter wrap at most */
    clock->last_ticks = now;
    if (clock->den == 1u) {
        clock->us += delta * clock->num; /* whole microseconds per tick; wraps at 2^32 by design */
    } else {
        /* delta = q * den + r: q * den ticks are exactly q * num us; the rest carries the remainder */
        uint32_t r;
        const uint32_t q = pfw_divmod_u32(delta, clock->den, &r);
        const uint32_t acc = clock->rem + (r * clock->num); /* <= (den - 1) * (num + 1): fits, by init */
        clock->us += (q * clock->num) + pfw_divmod_u32(acc, clock->den, &clock->rem); /* modulo 2^32 */
    }
    return clock->us;
}

/* ------------------------------------------------------------------ rate */
uint32_t pfw_period_us(uint32_t rate_hz)
{
    uint32_t unused;
    return ((rate_hz == 0u) || (rate_hz > PFW_MAX_RATE_HZ)) ? 0u : pfw_divmod_u32(PFW_US_PER_S, rate_hz, &unused);
}

int pfw_pacer_init(pfw_pacer_t *pacer, uint32_t rate_hz, uint32_t first_us)
{
    int status = -1;
    if ((rate_hz != 0u) && (rate_hz <= PFW_MAX_RATE_HZ)) {
        pacer->rate_hz = rate_hz;
        pacer->period_us = pfw_divmod_u32(PFW_US_PER_S, rate_hz, &pacer->frac);
        pacer->acc = 0u;
        pacer->next_us = first_us;
        status = 0;
    }
    return status;
}

bool pfw_pacer_due(const pfw_pacer_t *pacer, uint32_t now_us)
{
    return pfw_time_diff_us(now_us, pacer->next_us) >= 0;
}

uint32_t pfw_pacer_advance(pfw_pacer_t *pacer)
{
    const uint32_t due = pacer->next_us;
    uint32_t step = pacer->period_us;
    pacer->acc += pacer->frac; /* < 2 * rate_hz <= 2e6: no overflow */
    if (pacer->acc >= pacer->rate_hz) {
        pacer->acc -= pacer->rate_hz;
        step += 1u;
    }
    pacer->next_us = due + step; /* wraps at 2^32 by design */
    return due;
}
