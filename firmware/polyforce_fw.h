/*
 * polyforce_fw.h - portable core of the polyforce bridge-ADC firmware (C99).
 *
 * The device end of polyforce_ros/serial_protocol.py: one 14-byte frame per
 * ADC sample, little-endian,
 *
 *     offset size field
 *     0      2    sync 0xA5 0x5A
 *     2      2    seq    uint16, +1 per conversion, wraps 0xFFFF -> 0
 *     4      4    t_us   uint32, device clock at the conversion (us), wraps 2^32 -> 0
 *     8      4    counts int32, ADC reading (two's complement)
 *     12     2    crc    CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF) of bytes 2..11
 *
 * What is here, none of it touching hardware, the heap or an OS:
 *   - frame encoding (pfw_encode_frame) and the CRC;
 *   - the sequence and device-clock rules (pfw_seq_next, pfw_time_diff_us);
 *   - a single-producer / single-consumer ring buffer between the ADC interrupt
 *     (producer) and the UART writer in the main loop (consumer);
 *   - a drift-free microsecond clock from any free-running hardware tick
 *     counter (pfw_clock_*), and the sample-rate bookkeeping (pfw_pacer_*,
 *     pfw_period_us);
 *   - 24-bit two's complement ADC words to int32 (pfw_counts_from_be24).
 *
 * Coding rules (MISRA-minded): fixed-width types only; all arithmetic on
 * unsigned types (wrap-around is defined) or on values proven in range; no
 * signed shifts, no conversion of out-of-range values to signed types; no
 * recursion, no dynamic memory, no library calls (on 8-bit AVR the compiler
 * itself calls libgcc for 32-bit multiply and divide).
 *
 * Concurrency rules of the ring (pfw_ring_t):
 *   - exactly one producer context (the ADC/DRDY interrupt) calls
 *     pfw_ring_record / pfw_ring_push; exactly one consumer context (the main
 *     loop) calls pfw_ring_pop / pfw_ring_pop_frame;
 *   - head is written only by the producer, tail only by the consumer; both
 *     are free-running counters (slot = index & (capacity - 1)), so "full" is
 *     head - tail == capacity and "empty" is head == tail, with no wasted slot
 *     and no shared flag;
 *   - each side reads the other's index once (a volatile load), then
 *     PFW_BARRIER(), then touches the slot, then PFW_BARRIER(), then publishes
 *     its own index (a volatile store). The barriers keep the compiler (and, on
 *     multi-core hosts, the CPU) from moving slot accesses across the index
 *     update, which is the acquire/release pairing the algorithm needs;
 *   - an index load/store must be a single, untearable access: the index type
 *     PFW_RING_INDEX_T defaults to uint32_t (32-bit cores) and to uint8_t on
 *     AVR, where 16/32-bit loads are not atomic. The capacity must be a power
 *     of two no larger than half the index range (checked at compile time);
 *   - a full ring refuses the new sample and counts it in `overflows`; unread
 *     data is never overwritten. The sequence number is assigned before the
 *     push, so every refused sample shows up at the host as a sequence gap
 *     (FrameParser.lost_frames).
 *   - `overflows` is uint32_t, written only by the producer; on targets where
 *     a 32-bit load is not atomic read it with interrupts masked.
 */
#ifndef POLYFORCE_FW_H
#define POLYFORCE_FW_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ frame */
#define PFW_FRAME_SIZE 14u
#define PFW_SYNC0 0xA5u
#define PFW_SYNC1 0x5Au
#define PFW_CRC_INIT 0xFFFFu

/** CRC-16/CCITT-FALSE (poly 0x1021, no reflection, no final xor), continuing from `crc`. */
uint16_t pfw_crc16_ccitt(const uint8_t *data, size_t len, uint16_t crc);

/** Encodes one frame into `out` (PFW_FRAME_SIZE bytes). */
void pfw_encode_frame(uint8_t out[PFW_FRAME_SIZE], uint16_t seq, uint32_t t_us, int32_t counts);

/** The sequence number after `seq` (wraps 0xFFFF -> 0). */
uint16_t pfw_seq_next(uint16_t seq);

/**
 * Signed difference a - b of two wrapping 32-bit device times (us), exact
 * whenever the true difference lies in [-2^31, 2^31). Pure unsigned arithmetic;
 * no implementation-defined conversion.
 */
int32_t pfw_time_diff_us(uint32_t a, uint32_t b);

/** A 24-bit two's complement word, most significant byte first (ADS1220 data) -> int32. */
int32_t pfw_counts_from_be24(uint8_t msb, uint8_t mid, uint8_t lsb);

/* --------------------------------------------------------------- messages */
/*
 * Messages: the device's identity (info), its health (status) and the ADC's
 * own temperature, on the same link as the sample frames, at frame boundaries.
 *
 *     offset size field
 *     0      2    sync 0xA5 0xC3
 *     2      ...  the body below, stuffed: every 0xA5 byte is followed by 0x00
 *
 *     body   size field
 *     0      1    type     PFW_MSG_INFO / PFW_MSG_STATUS / PFW_MSG_TEMPERATURE
 *     1      1    version  layout version of this type's payload (1)
 *     2      1    len      payload length, 0..PFW_MSG_PAYLOAD_MAX
 *     3      1    ~len     len xor 0xFF
 *     4      len  payload  little-endian fields (pfw_encode_info/_status/_temperature)
 *     4+len  2    crc      CRC-16/CCITT-FALSE of body bytes 0 .. 3+len
 *
 * The stuffing keeps the sample sync 0xA5 0x5A out of every message (and no
 * message starts with 0x5A or ends with 0xA5), so a host that knows only the
 * 14-byte sample frame skips messages as line noise without one CRC error.
 * A host reads a new layout version of a known type by its length: fields are
 * only ever appended.
 *
 * Requests from the host, one ASCII byte each: 'I' (PFW_REQUEST_INFO) for an
 * info message, 'S' (PFW_REQUEST_STATUS) for a status message.
 */
#define PFW_MSG_SYNC1 0xC3u
#define PFW_MSG_STUFF 0x00u
#define PFW_MSG_PAYLOAD_MAX 64u
#define PFW_MSG_MAX_SIZE (2u + 2u * (4u + PFW_MSG_PAYLOAD_MAX + 2u))
#define PFW_MSG_INFO 0x01u
#define PFW_MSG_STATUS 0x02u
#define PFW_MSG_TEMPERATURE 0x03u
#define PFW_REQUEST_INFO 0x49u   /* 'I' */
#define PFW_REQUEST_STATUS 0x53u /* 'S' */

/* The link protocol (sample frames and messages) and this firmware's version. */
#define PFW_PROTOCOL_VERSION 1u
#define PFW_FW_VERSION_MAJOR 1u
#define PFW_FW_VERSION_MINOR 1u
#define PFW_FW_VERSION_PATCH 0u

/* Why the device last started (status message). */
#define PFW_RESET_UNKNOWN 0u
#define PFW_RESET_POWER_ON 1u
#define PFW_RESET_EXTERNAL 2u /* reset pin or button */
#define PFW_RESET_BROWN_OUT 3u
#define PFW_RESET_WATCHDOG 4u
#define PFW_RESET_SOFTWARE 5u /* a reset requested by software (or by the host, e.g. the bootloader) */

/* mains_filter of the info message: the ADS1220's FIR filter setting (register 2, bits 5:4). */
#define PFW_MAINS_OFF 0u
#define PFW_MAINS_50_60 1u
#define PFW_MAINS_50 2u
#define PFW_MAINS_60 3u

#define PFW_INFO_ADC_LEN 8u
#define PFW_INFO_BOARD_LEN 16u
#define PFW_INFO_SERIAL_LEN 16u

/**
 * Who the device is (info message, version 1, 56 bytes). volts_per_count
 * follows from it: vref_uv 1e-6 / (gain 2^(adc_bits - 1)) V per count.
 * Strings are NUL-terminated or fill their field; they are sent NUL-padded.
 */
typedef struct {
    uint32_t rate_hz;                   /* conversions per second */
    uint32_t vref_uv;                   /* ADC reference (= bridge excitation when ratiometric), uV */
    uint16_t gain;                      /* PGA gain */
    uint8_t adc_bits;                   /* ADC resolution (two's complement), e.g. 24 */
    uint8_t mains_filter;               /* PFW_MAINS_* */
    char adc[PFW_INFO_ADC_LEN];         /* e.g. "ADS1220" */
    char board[PFW_INFO_BOARD_LEN];     /* e.g. "arduino-zero" */
    char serial[PFW_INFO_SERIAL_LEN];   /* the sensor's serial number */
} pfw_info_t;

/** The device's health (status message, version 1, 20 bytes). */
typedef struct {
    uint32_t t_us;            /* device time when sent */
    uint8_t reset_reason;     /* PFW_RESET_* of the last start */
    uint16_t watchdog_resets; /* watchdog resets since power-on */
    uint32_t overflows;       /* conversions refused by the full ring since start */
    uint32_t adc_reconfigs;   /* times the ADC was configured again because DRDY fell silent */
    uint32_t uptime_s;        /* seconds since start */
} pfw_status_t;

/**
 * Encodes a message of `type` with `len` payload bytes into `out`
 * (PFW_MSG_MAX_SIZE bytes suffice); returns its size, or 0 when len is too large.
 */
size_t pfw_encode_message(uint8_t *out, uint8_t type, uint8_t version, const uint8_t *payload, size_t len);

/** Encodes an info message (protocol and firmware version from this header); returns its size. */
size_t pfw_encode_info(uint8_t *out, const pfw_info_t *info);

/** Encodes a status message; returns its size. */
size_t pfw_encode_status(uint8_t *out, const pfw_status_t *status);

/**
 * Encodes a temperature message: device time and the temperature in 1/32 degC
 * (the ADS1220 sensor's own resolution, 0.03125 degC); returns its size.
 */
size_t pfw_encode_temperature(uint8_t *out, uint32_t t_us, int16_t temp_q5);

/**
 * ADS1220 temperature-sensor word (TS = 1): the first two data bytes hold a
 * 14-bit two's complement value, left-justified, in 1/32 degC.
 */
int16_t pfw_ads1220_temp_q5(uint8_t msb, uint8_t mid);

/* ------------------------------------------------------------------ ring */
/*
 * Ring capacity (a power of two): 256 samples on 32-bit cores; 64 on AVR,
 * whose 8-bit indices allow at most 128 and whose RAM is 2 KB on an Uno.
 */
#ifndef PFW_RING_CAPACITY
#if defined(__AVR__)
#define PFW_RING_CAPACITY 64u
#else
#define PFW_RING_CAPACITY 256u
#endif
#endif

#ifndef PFW_RING_INDEX_T
#if defined(__AVR__)
#define PFW_RING_INDEX_T uint8_t
#else
#define PFW_RING_INDEX_T uint32_t
#endif
#endif

typedef PFW_RING_INDEX_T pfw_index_t;

/* Compile-time checks (C99 has no _Static_assert): a negative array size fails the build. */
typedef char pfw_check_capacity_power_of_two[((PFW_RING_CAPACITY >= 2u) &&
                                              ((PFW_RING_CAPACITY & (PFW_RING_CAPACITY - 1u)) == 0u)) ? 1 : -1];
typedef char pfw_check_capacity_fits_index[((pfw_index_t)(2u * PFW_RING_CAPACITY - 1u) ==
                                            (2u * PFW_RING_CAPACITY - 1u)) ? 1 : -1];

/*
 * The barrier between slot accesses and index updates. The default is a full
 * fence on GCC/Clang (a compiler barrier plus, where the target has one, a
 * memory barrier: DMB on Cortex-M, MFENCE on x86); on AVR, single-core and in
 * order, a compiler barrier suffices. Other compilers must define it.
 */
#ifndef PFW_BARRIER
#if (defined(__GNUC__) || defined(__clang__)) && defined(__ATOMIC_SEQ_CST) && !defined(__AVR__)
#define PFW_BARRIER() __atomic_thread_fence(__ATOMIC_SEQ_CST)
#elif defined(__GNUC__) || defined(__clang__)
#define PFW_BARRIER() __asm__ __volatile__("" ::: "memory")
#else
#error "polyforce_fw: define PFW_BARRIER() as a compiler and memory barrier for this toolchain"
#endif
#endif

/** One conversion as recorded by the interrupt. */
typedef struct {
    uint32_t t_us;
    int32_t counts;
    uint16_t seq;
} pfw_sample_t;

typedef struct {
    pfw_sample_t slot[PFW_RING_CAPACITY];
    volatile pfw_index_t head;   /* next slot to fill; written by the producer only */
    volatile pfw_index_t tail;   /* next slot to read; written by the consumer only */
    volatile uint32_t overflows; /* samples refused because the ring was full; producer only */
    uint16_t next_seq;           /* sequence number of the next conversion; producer only */
} pfw_ring_t;

/** Empties the ring; the next recorded conversion gets `first_seq`. Call before either side runs. */
void pfw_ring_init(pfw_ring_t *ring, uint16_t first_seq);

/** Producer: stores a copy of `sample`. Returns false (and counts an overflow) when full. */
bool pfw_ring_push(pfw_ring_t *ring, const pfw_sample_t *sample);

/**
 * Producer: records one conversion, numbered with the next sequence number
 * whether or not it fits (a refused sample becomes a sequence gap at the host).
 */
bool pfw_ring_record(pfw_ring_t *ring, uint32_t t_us, int32_t counts);

/** Consumer: takes the oldest sample into `out`. Returns false when empty. */
bool pfw_ring_pop(pfw_ring_t *ring, pfw_sample_t *out);

/** Consumer: takes the oldest sample and encodes it as a frame. Returns false when empty. */
bool pfw_ring_pop_frame(pfw_ring_t *ring, uint8_t out[PFW_FRAME_SIZE]);

/** Number of unread samples (a snapshot; exact from either side's point of view). */
uint32_t pfw_ring_count(const pfw_ring_t *ring);

/* ------------------------------------------------------------------ division */
/*
 * Cores without a divide instruction (Cortex-M0/M0+, ARMv6-M) would call the
 * compiler's runtime (__aeabi_uidiv) for every `/` and `%`. There the core
 * divides with its own shift-and-subtract routine instead (32 steps, constant
 * time), so it links no library function on any ARM core. Define
 * PFW_SOFT_DIVIDE to 0 or 1 to override the choice.
 */
#ifndef PFW_SOFT_DIVIDE
#if defined(__arm__) && !defined(__ARM_FEATURE_IDIV)
#define PFW_SOFT_DIVIDE 1
#else
#define PFW_SOFT_DIVIDE 0
#endif
#endif

/** n / d, with n % d in *rem (d != 0); the routine every division of the core goes through. */
uint32_t pfw_divmod_u32(uint32_t n, uint32_t d, uint32_t *rem);

/* ------------------------------------------------------------------ clock */
/**
 * Device microsecond clock from a free-running hardware counter of
 * `counter_bits` bits counting at `tick_hz`. The conversion carries the
 * remainder, so it never drifts from the counter (no rounding accumulates),
 * and the result wraps at 2^32 like the frame's t_us.
 *
 * With 1e6 / tick_hz reduced to num / den, pfw_clock_update costs two
 * divisions and no loop, for any tick step. That needs (den - 1) * (num + 1)
 * < 2^32, and pfw_clock_init refuses tick rates that break it. Every multiple
 * of 1 kHz below 4 GHz qualifies, as do the divisors of 1 MHz, 32768 Hz and the
 * UART crystals (11.0592, 14.7456 MHz); refused are rates such as 999999 Hz or
 * 4294967291 Hz, whose reduced fraction has both terms large.
 *
 * pfw_clock_update must see every counter wrap: call it at least once per
 * 2^counter_bits ticks, from one context only (or with interrupts masked).
 */
typedef struct {
    uint32_t num;        /* 1e6 / gcd(1e6, tick_hz) */
    uint32_t den;        /* tick_hz / gcd(1e6, tick_hz) */
    uint32_t mask;       /* counter width */
    uint32_t last_ticks; /* counter value at the last update */
    uint32_t rem;        /* fraction of a microsecond carried, in 1/den us; < den */
    uint32_t us;         /* the clock */
} pfw_clock_t;

/**
 * Returns 0, or -1 (and leaves `clock` untouched) when tick_hz is 0,
 * counter_bits is not in 1..32, or the tick rate's reduced fraction is too
 * large for an exact loop-free update (see above).
 */
int pfw_clock_init(pfw_clock_t *clock, uint32_t tick_hz, uint32_t counter_bits, uint32_t ticks_now, uint32_t us_start);

/** Advances the clock to the counter value `ticks_now` and returns it (us). Constant time. */
uint32_t pfw_clock_update(pfw_clock_t *clock, uint32_t ticks_now);

/* ------------------------------------------------------------------ rate */
#define PFW_MAX_RATE_HZ 1000000u

/** Whole microseconds of one sample period (1e6 / rate, rounded down); 0 for an invalid rate. */
uint32_t pfw_period_us(uint32_t rate_hz);

/**
 * Sample instants on the device clock at `rate_hz`: sample k is due at
 * first + floor(k * 1e6 / rate_hz) us (mod 2^32), computed incrementally with
 * the remainder carried, so rates that do not divide 1e6 (3 kHz: 333.33 us)
 * keep their exact mean period forever.
 */
typedef struct {
    uint32_t rate_hz;
    uint32_t period_us; /* whole microseconds per period */
    uint32_t frac;      /* 1e6 mod rate_hz */
    uint32_t acc;       /* carried fraction, < rate_hz */
    uint32_t next_us;   /* device time of the next sample */
} pfw_pacer_t;

/** Returns 0, or -1 when rate_hz is 0 or above PFW_MAX_RATE_HZ. */
int pfw_pacer_init(pfw_pacer_t *pacer, uint32_t rate_hz, uint32_t first_us);

/** True when the next sample is due at device time `now_us` (wrap-safe). */
bool pfw_pacer_due(const pfw_pacer_t *pacer, uint32_t now_us);

/** Returns the due time of the next sample and schedules the one after it. */
uint32_t pfw_pacer_advance(pfw_pacer_t *pacer);

#ifdef __cplusplus
}
#endif

#endif /* POLYFORCE_FW_H */
