/*
 * virtual_device.c - the polyforce bridge-ADC firmware, run on a PC against a pseudo-terminal.
 *
 * Built from the same core as the board sketch (../polyforce_fw.c): the
 * simulated ADC "interrupt" records conversions into the pfw ring at the
 * instants of a pfw pacer on a pfw clock, and the "UART writer" pops frames
 * and writes them to the pty master. driver_node (backend serial) opens the
 * slave side as if it were /dev/ttyACM0.
 *
 * The device's crystal can be off by --ppm (positive: the device clock runs
 * fast): its hardware tick counter runs at 1 GHz x (1 + ppm 1e-6) of host
 * time, and the core turns those ticks into the frame's microsecond clock.
 *
 * usage: virtual_device [options]
 *   --rate HZ           conversions per second (default 1000)
 *   --ppm PPM           crystal error of the device, + = fast (default 0)
 *   --link PATH         keep a symlink PATH -> current pty slave (like /dev/serial/by-id/...)
 *   --signal sine|step  simulated sensor in counts (default sine)
 *   --amplitude N       counts (default 4000000)     --offset N   counts (default 100000)
 *   --freq HZ           sine frequency or step rate (default 1.7)
 *   --seq0 N            first sequence number (default 0)  --t0-us N  first device time (default 0)
 *   --baud N            wire rate limit, 10 bits per byte (default 0 = as fast as the pty takes)
 *   --log FILE          one line per event (see below)
 *   --seed N            noise seed (default 1)
 *   --duration S        exit after S seconds (default 0 = run until "quit", EOF on stdin or SIGINT)
 *   --serial TEXT       sensor serial number in the info message (default VIRTUAL-0001)
 *   --board TEXT        board name in the info message (default virtual)
 *   --vref-uv N         reference in the info message, uV (default 5000000)
 *   --gain N            PGA gain in the info message (default 128): with 24 bits, volts_per_count =
 *                       vref / (gain 2^23); 8000000 and 1 give 2^-20
 *   --status-period S   a status message every S seconds (default 1; 0 = on request only)
 *   --temp-period S     a temperature message every S seconds (default 1; 0 = none)
 *   --temperature C     the simulated ADC temperature (default 25)
 *
 * Messages (info, status, temperature; polyforce_fw.h) go out between frames: info and status
 * at every start (power-on, reset, watchdog reset) and after a rate change, status and
 * temperature periodically, and info / status when the host writes 'I' / 'S' to the port.
 *
 * Commands on stdin, one per line; each is acknowledged with "ok <command>" on stdout:
 *   unplug        close the pty and remove the link (the USB cable is pulled)
 *   plug          a new pty, the link points to it (plugged back in)
 *   noise N       N bytes (1..1000) of line noise before the next frame
 *   dropbyte      the next frame loses one byte
 *   reset         device reset: sequence and clock restart at 0 (ring emptied)
 *   watchdog      the firmware hangs; the watchdog resets the device (like reset, but reported
 *                 with reset reason watchdog and one more watchdog reset)
 *   temp C        the ADC's temperature becomes C degC
 *   rate HZ       change the conversion rate (e.g. a too slow ADC setting)
 *   baud N        change the wire rate limit (0 = none): a link too slow for the rate
 *   status        print counters
 *   quit
 * stdout also carries "pty PATH" whenever a pty is created and "unplugged" when it goes.
 *
 * Log lines (--log), times in CLOCK_REALTIME ns (the clock of ROS stamps):
 *   F seq t_us counts acq_ns write_ns   a complete, valid frame was written; acq_ns is the
 *                                       host instant at which the device clock read t_us
 *   X seq t_us counts acq_ns write_ns   a frame written with a byte missing (must never be published)
 *   N nbytes write_ns                   line noise written
 *   M info|status|temperature write_ns  a message written
 *   E event write_ns                    unplug | plug | reset | watchdog | rate HZ | baud N | temp C
 *
 * While nobody has the slave open, or while unplugged, frames are produced and
 * discarded (a USB device without a host), so a late reader gets no backlog.
 * Faults that cut the stream (noise, dropbyte, reset) take effect at a frame
 * boundary, so each one costs the driver a known, countable amount.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "../polyforce_fw.h"

#define TICK_HZ 1000000000u /* the simulated hardware counter: nominally 1 GHz, 32 bits */
#define OUT_CAP 2048u
#define NOISE_MAX 1000u

enum out_kind { OUT_NONE, OUT_FRAME, OUT_CORRUPT, OUT_NOISE, OUT_MESSAGE };

typedef struct {
    /* options */
    uint32_t rate_hz;
    double ppm;
    const char *link;
    int step_signal;
    double amplitude, offset, freq;
    uint16_t seq0;
    uint32_t t0_us;
    uint32_t baud;
    FILE *log;
    uint64_t rng;
    double duration_s;
    pfw_info_t info;
    double status_period_s, temp_period_s, temperature_c;

    /* the pty */
    int master;
    char slave[128];

    /* the firmware */
    pfw_ring_t ring;
    pfw_clock_t clock;
    pfw_pacer_t pacer;
    uint64_t sample_index; /* conversions since (re)start: the simulated sensor's time axis */

    /* the simulated crystal: device ticks = (host - mono0) * (1 + ppm 1e-6) */
    int64_t mono0_ns;
    int64_t rt_minus_mono_ns;
    uint64_t ticks;         /* unwrapped tick count */
    uint64_t fed_ticks;     /* last count shown to the core's clock */
    uint64_t ticks_origin;  /* tick count when the device clock last started */
    uint32_t us_origin;     /* device clock value at that instant */

    /* the wire */
    uint8_t out[OUT_CAP];
    size_t out_len, out_pos;
    enum out_kind kind;
    pfw_sample_t out_sample;
    double tokens;
    int64_t tokens_ns;

    /* pending faults */
    uint32_t noise_pending;
    int drop_pending;
    int reset_pending;
    int watchdog_pending;

    /* messages: pending ones go out at the next frame boundary */
    int info_pending, status_pending, temp_pending;
    const char *msg_name;
    int64_t next_status_mono, next_temp_mono;
    uint8_t reset_reason;
    uint16_t watchdog_resets; /* survives a watchdog reset (like a no-init RAM word), not a power-on */
    int64_t start_mono;       /* host instant of the last device start: uptime */

    /* counters */
    uint64_t written_frames, discarded_frames, noise_bytes, dropped_bytes, resets, written_messages, requests;

    char cmd[512];
    size_t cmd_len;
} vdev_t;

static volatile sig_atomic_t stop_requested = 0;

static void on_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
}

static int64_t now_ns(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static uint64_t rng_next(vdev_t *d)
{ /* xorshift64* */
    d->rng ^= d->rng >> 12u;
    d->rng ^= d->rng << 25u;
    d->rng ^= d->rng >> 27u;
    return d->rng * 0x2545F4914F6CDD1Du;
}

static void log_line(vdev_t *d, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void log_line(vdev_t *d, const char *fmt, ...)
{
    va_list ap;
    if (d->log == NULL) {
        return;
    }
    va_start(ap, fmt);
    vfprintf(d->log, fmt, ap);
    va_end(ap);
}

static void say(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void say(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    fflush(stdout);
}

/* ------------------------------------------------------------------ time */
static uint64_t ticks_at(const vdev_t *d, int64_t mono)
{
    const double e = (double)(mono - d->mono0_ns);
    return (uint64_t)llround(e * (1.0 + d->ppm * 1e-6));
}

static int64_t mono_at_ticks(const vdev_t *d, uint64_t ticks)
{
    return d->mono0_ns + (int64_t)ceil((double)ticks / (1.0 + d->ppm * 1e-6));
}

/* Host CLOCK_REALTIME ns at which the device clock read `t_us` (the conversion instant). */
static int64_t acquisition_rt_ns(const vdev_t *d, uint32_t t_us)
{
    /* unwrapped device microseconds since the clock (re)started; the clock counts whole us */
    const uint64_t elapsed_now_us = (d->ticks - d->ticks_origin) / 1000u;
    const uint32_t back = (uint32_t)(d->us_origin + (uint32_t)elapsed_now_us) - t_us; /* < 2^31 */
    const uint64_t elapsed_us = elapsed_now_us - back;
    return mono_at_ticks(d, d->ticks_origin + elapsed_us * 1000u) + d->rt_minus_mono_ns;
}

static void start_device_clock(vdev_t *d, uint32_t us_start, uint16_t seq_start)
{
    pfw_ring_init(&d->ring, seq_start);
    d->ticks_origin = d->ticks;
    d->us_origin = us_start;
    (void)pfw_clock_init(&d->clock, TICK_HZ, 32u, (uint32_t)d->ticks, us_start);
    d->fed_ticks = d->ticks;
    (void)pfw_pacer_init(&d->pacer, d->rate_hz, us_start);
    d->sample_index = 0u;
    /* a starting firmware says who it is and why it started */
    d->start_mono = now_ns(CLOCK_MONOTONIC);
    d->info_pending = 1;
    d->status_pending = 1;
}

/* ------------------------------------------------------------------ the pty */
static void update_link(const vdev_t *d)
{
    char tmp[4200];
    if (d->link == NULL) {
        return;
    }
    snprintf(tmp, sizeof tmp, "%s.tmp%ld", d->link, (long)getpid());
    unlink(tmp);
    if (symlink(d->slave, tmp) != 0 || rename(tmp, d->link) != 0) {
        fprintf(stderr, "virtual_device: cannot link %s -> %s: %s\n", d->link, d->slave, strerror(errno));
        exit(1);
    }
}

static void plug(vdev_t *d)
{
    struct termios tio;
    int slave;
    const char *name;
    d->master = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (d->master < 0 || grantpt(d->master) != 0 || unlockpt(d->master) != 0 || (name = ptsname(d->master)) == NULL) {
        fprintf(stderr, "virtual_device: no pty: %s\n", strerror(errno));
        exit(1);
    }
    snprintf(d->slave, sizeof d->slave, "%s", name);
    /* On Linux the termios of a pty master are the slave's: raw, so no byte is translated or
       swallowed (0x0D, 0x11, 0x13, 0x03...) even before the reader configures the port. */
    if (tcgetattr(d->master, &tio) == 0) {
        cfmakeraw(&tio);
        (void)tcsetattr(d->master, TCSANOW, &tio);
    }
    /* Open and close the slave once: from then on the master reports POLLHUP until a reader opens it. */
    slave = open(d->slave, O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (slave >= 0) {
        close(slave);
    }
    update_link(d);
    d->out_len = d->out_pos = 0u;
    d->kind = OUT_NONE;
    say("pty %s\n", d->slave);
}

static void unplug(vdev_t *d)
{
    if (d->master >= 0) {
        close(d->master);
        d->master = -1;
    }
    if (d->link != NULL) {
        unlink(d->link);
    }
    d->out_len = d->out_pos = 0u;
    d->kind = OUT_NONE;
    say("unplugged\n");
}

/* True when the pty exists and a reader has the slave open. */
static int reader_present(const vdev_t *d)
{
    struct pollfd p;
    if (d->master < 0) {
        return 0;
    }
    p.fd = d->master;
    p.events = POLLOUT;
    p.revents = 0;
    return poll(&p, 1, 0) >= 0 && (p.revents & POLLHUP) == 0;
}

/* ------------------------------------------------------------------ the sensor */
static int32_t sensor_counts(const vdev_t *d, uint64_t k)
{
    const double t = (double)k / (double)d->rate_hz;
    double v;
    if (d->step_signal) {
        v = d->offset + ((((uint64_t)floor(t * d->freq)) & 1u) ? d->amplitude : 0.0);
    } else {
        v = d->offset + d->amplitude * sin(2.0 * M_PI * d->freq * t);
    }
    if (v > 2147483647.0) {
        v = 2147483647.0;
    }
    if (v < -2147483648.0) {
        v = -2147483648.0;
    }
    return (int32_t)llround(v);
}

/* ------------------------------------------------------------------ faults */
/* Would FrameParser accept a frame starting at a sync word other than the real frame starts? */
static int false_frame_at(const uint8_t *buf, size_t len, size_t i)
{
    uint8_t body[10];
    uint16_t crc;
    if (i + PFW_FRAME_SIZE > len || buf[i] != PFW_SYNC0 || buf[i + 1u] != PFW_SYNC1) {
        return 0;
    }
    memcpy(body, &buf[i + 2u], sizeof body);
    crc = pfw_crc16_ccitt(body, sizeof body, (uint16_t)PFW_CRC_INIT);
    return buf[i + 12u] == (uint8_t)(crc & 0xFFu) && buf[i + 13u] == (uint8_t)(crc >> 8u);
}

/*
 * Line noise: random bytes with a few embedded sync words (so the parser must
 * reject candidates by CRC). Redrawn until no candidate happens to carry a
 * valid CRC (a 1 in 65536 event no 16-bit CRC can catch), and with no sync word
 * starting in the last 13 bytes, so no candidate reaches into the next frame.
 */
static size_t make_noise(vdev_t *d, uint8_t *dst, size_t n)
{
    size_t i;
    int clean;
    do {
        clean = 1;
        for (i = 0u; i < n; ++i) {
            dst[i] = (uint8_t)(rng_next(d) >> 56u);
        }
        if (n >= PFW_FRAME_SIZE) { /* at least one sync word the parser must look at */
            const size_t at = (size_t)(rng_next(d) % (uint64_t)(n - PFW_FRAME_SIZE + 1u));
            dst[at] = (uint8_t)PFW_SYNC0;
            dst[at + 1u] = (uint8_t)PFW_SYNC1;
        }
        for (i = 0u; i + 1u < n; ++i) {
            if (dst[i] == PFW_SYNC0 && dst[i + 1u] == PFW_SYNC1) {
                if (i + PFW_FRAME_SIZE > n || false_frame_at(dst, n, i)) {
                    clean = 0;
                }
            }
        }
    } while (!clean);
    return n;
}

/* ------------------------------------------------------------------ the writer */
/* The firmware's health report as of now. */
static pfw_status_t device_status(const vdev_t *d)
{
    pfw_status_t st;
    st.t_us = d->clock.us;
    st.reset_reason = d->reset_reason;
    st.watchdog_resets = d->watchdog_resets;
    st.overflows = d->ring.overflows;
    st.adc_reconfigs = 0u; /* the simulated ADC never falls silent */
    st.uptime_s = (uint32_t)((now_ns(CLOCK_MONOTONIC) - d->start_mono) / 1000000000);
    return st;
}

/* One pending message into the output buffer: info first, then status, then temperature. */
static void fill_message(vdev_t *d)
{
    if (d->info_pending) {
        d->info.rate_hz = d->rate_hz;
        d->out_len = pfw_encode_info(d->out, &d->info);
        d->info_pending = 0;
        d->msg_name = "info";
    } else if (d->status_pending) {
        const pfw_status_t st = device_status(d);
        d->out_len = pfw_encode_status(d->out, &st);
        d->status_pending = 0;
        d->msg_name = "status";
    } else {
        d->out_len = pfw_encode_temperature(d->out, d->clock.us, (int16_t)lround(d->temperature_c * 32.0));
        d->temp_pending = 0;
        d->msg_name = "temperature";
    }
    d->kind = OUT_MESSAGE;
}

static void fill_out(vdev_t *d)
{
    pfw_sample_t s;
    if (d->out_pos < d->out_len) {
        return; /* still sending */
    }
    d->out_len = d->out_pos = 0u;
    d->kind = OUT_NONE;
    if (d->noise_pending > 0u) {
        d->out_len = make_noise(d, d->out, d->noise_pending);
        d->noise_pending = 0u;
        d->kind = OUT_NOISE;
        return;
    }
    if (d->info_pending || d->status_pending || d->temp_pending) {
        fill_message(d);
        return;
    }
    if (!pfw_ring_pop(&d->ring, &s)) {
        return;
    }
    pfw_encode_frame(d->out, s.seq, s.t_us, s.counts);
    d->out_len = PFW_FRAME_SIZE;
    d->out_sample = s;
    d->kind = OUT_FRAME;
    if (d->drop_pending) {
        /* drop a byte of the counts field; the truncated frame followed by the next frame's
           sync byte must not pass the CRC by chance, else drop another byte */
        size_t drop;
        for (drop = 9u; drop < PFW_FRAME_SIZE - 1u; ++drop) {
            uint8_t probe[PFW_FRAME_SIZE];
            memcpy(probe, d->out, drop);
            memcpy(&probe[drop], &d->out[drop + 1u], PFW_FRAME_SIZE - 1u - drop);
            probe[PFW_FRAME_SIZE - 1u] = (uint8_t)PFW_SYNC0;
            if (!false_frame_at(probe, sizeof probe, 0u)) {
                break;
            }
        }
        memmove(&d->out[drop], &d->out[drop + 1u], PFW_FRAME_SIZE - 1u - drop);
        d->out_len = PFW_FRAME_SIZE - 1u;
        d->kind = OUT_CORRUPT;
        d->drop_pending = 0;
        d->dropped_bytes++;
    }
}

static void finish_out(vdev_t *d, int64_t write_rt)
{
    switch (d->kind) {
    case OUT_FRAME:
    case OUT_CORRUPT:
        log_line(d, "%c %u %" PRIu32 " %" PRId32 " %" PRId64 " %" PRId64 "\n", d->kind == OUT_FRAME ? 'F' : 'X',
                 (unsigned)d->out_sample.seq, d->out_sample.t_us, d->out_sample.counts,
                 acquisition_rt_ns(d, d->out_sample.t_us), write_rt);
        d->written_frames++;
        break;
    case OUT_NOISE:
        log_line(d, "N %zu %" PRId64 "\n", d->out_len, write_rt);
        d->noise_bytes += d->out_len;
        break;
    case OUT_MESSAGE:
        log_line(d, "M %s %" PRId64 "\n", d->msg_name, write_rt);
        d->written_messages++;
        break;
    case OUT_NONE:
    default:
        break;
    }
    d->kind = OUT_NONE;
    d->out_len = d->out_pos = 0u;
}

/* Moves bytes towards the wire; returns 1 while output is held back by the baud limit or a full pty. */
static int pump(vdev_t *d, int64_t mono)
{
    if (d->baud > 0u) {
        const double bytes_per_ns = (double)d->baud / 10.0 * 1e-9;
        d->tokens += (double)(mono - d->tokens_ns) * bytes_per_ns;
        if (d->tokens > 64.0) { /* the wire idles when the 64-byte TX buffer (Arduino's) runs empty */
            d->tokens = 64.0;
        }
    }
    d->tokens_ns = mono;
    for (;;) {
        size_t n;
        ssize_t w;
        int64_t write_rt;
        fill_out(d);
        if (d->out_len == 0u) {
            return 0;
        }
        if (!reader_present(d)) {
            /* nobody listening (or unplugged): the conversion is made and lost, like on a real USB device */
            if (d->kind == OUT_FRAME || d->kind == OUT_CORRUPT) {
                d->discarded_frames++;
            }
            d->kind = OUT_NONE;
            d->out_len = d->out_pos = 0u;
            continue;
        }
        n = d->out_len - d->out_pos;
        if (d->baud > 0u) {
            const size_t budget = (size_t)d->tokens;
            if (budget == 0u) {
                return 1;
            }
            if (n > budget) {
                n = budget;
            }
        }
        write_rt = now_ns(CLOCK_REALTIME);
        w = write(d->master, &d->out[d->out_pos], n);
        if (w < 0) {
            if (errno == EAGAIN || errno == EINTR) {
                return 1; /* the pty is full: the reader is not keeping up; the ring absorbs it */
            }
            if (errno == EIO) { /* the reader closed between the check and the write */
                d->kind = OUT_NONE;
                d->out_len = d->out_pos = 0u;
                return 0;
            }
            fprintf(stderr, "virtual_device: write: %s\n", strerror(errno));
            exit(1);
        }
        if (d->baud > 0u) {
            d->tokens -= (double)w;
        }
        d->out_pos += (size_t)w;
        if (d->out_pos == d->out_len) {
            finish_out(d, write_rt);
        }
    }
}

/* ------------------------------------------------------------------ commands */
static void do_command(vdev_t *d, char *line)
{
    char word[32] = "";
    long arg = 0;
    int nargs = sscanf(line, "%31s %ld", word, &arg);
    const int64_t rt = now_ns(CLOCK_REALTIME);
    if (nargs < 1) {
        return;
    }
    if (strcmp(word, "unplug") == 0) {
        if (d->master >= 0) {
            unplug(d);
        }
        log_line(d, "E unplug %" PRId64 "\n", rt);
    } else if (strcmp(word, "plug") == 0) {
        if (d->master < 0) {
            plug(d);
        }
        log_line(d, "E plug %" PRId64 "\n", rt);
    } else if (strcmp(word, "noise") == 0 && nargs == 2 && arg >= 1 && arg <= (long)NOISE_MAX) {
        d->noise_pending = (uint32_t)arg;
    } else if (strcmp(word, "dropbyte") == 0) {
        d->drop_pending = 1;
    } else if (strcmp(word, "reset") == 0) {
        d->reset_pending = 1;
    } else if (strcmp(word, "watchdog") == 0) {
        d->reset_pending = 1;
        d->watchdog_pending = 1;
    } else if (strcmp(word, "temp") == 0 && nargs >= 1 && sscanf(line, "%*s %lf", &d->temperature_c) == 1) {
        log_line(d, "E temp %.3f %" PRId64 "\n", d->temperature_c, rt);
    } else if (strcmp(word, "rate") == 0 && nargs == 2 && arg >= 1 && arg <= (long)PFW_MAX_RATE_HZ) {
        d->rate_hz = (uint32_t)arg;
        (void)pfw_pacer_init(&d->pacer, d->rate_hz, d->pacer.next_us);
        d->info_pending = 1; /* the device's identity includes its rate */
        log_line(d, "E rate %ld %" PRId64 "\n", arg, rt);
    } else if (strcmp(word, "baud") == 0 && nargs == 2 && arg >= 0) {
        d->baud = (uint32_t)arg;
        d->tokens = 0.0;
        log_line(d, "E baud %ld %" PRId64 "\n", arg, rt);
    } else if (strcmp(word, "status") == 0) {
        say("status written=%" PRIu64 " discarded=%" PRIu64 " overflows=%" PRIu32 " queued=%" PRIu32
            " noise_bytes=%" PRIu64 " dropped_bytes=%" PRIu64 " resets=%" PRIu64 " next_seq=%u rate=%" PRIu32
            " baud=%" PRIu32 " messages=%" PRIu64 " requests=%" PRIu64 " watchdog_resets=%u\n",
            d->written_frames, d->discarded_frames, d->ring.overflows, pfw_ring_count(&d->ring), d->noise_bytes,
            d->dropped_bytes, d->resets, (unsigned)d->ring.next_seq, d->rate_hz, d->baud, d->written_messages,
            d->requests, (unsigned)d->watchdog_resets);
    } else if (strcmp(word, "quit") == 0) {
        stop_requested = 1;
    } else {
        say("error unknown command: %s\n", line);
        return;
    }
    say("ok %s\n", line);
}

/* The host's requests on the link: 'I' for info, 'S' for status; other bytes are ignored. */
static void read_requests(vdev_t *d)
{
    uint8_t buf[64];
    ssize_t r;
    ssize_t i;
    if (d->master < 0) {
        return;
    }
    r = read(d->master, buf, sizeof buf);
    for (i = 0; i < r; ++i) {
        if (buf[i] == PFW_REQUEST_INFO) {
            d->info_pending = 1;
            d->requests++;
        } else if (buf[i] == PFW_REQUEST_STATUS) {
            d->status_pending = 1;
            d->requests++;
        }
    }
}

/* One read per wake-up, so that an endless input cannot starve the conversions. */
static void read_commands(vdev_t *d)
{
    char *nl;
    ssize_t r;
    size_t i;
    if (d->cmd_len >= sizeof d->cmd - 1u) {
        d->cmd_len = 0u; /* an absurdly long line: forget it */
    }
    r = read(STDIN_FILENO, &d->cmd[d->cmd_len], sizeof d->cmd - 1u - d->cmd_len);
    if (r == 0) {
        stop_requested = 1; /* our controller is gone */
        return;
    }
    if (r < 0) {
        return; /* EAGAIN */
    }
    for (i = d->cmd_len; i < d->cmd_len + (size_t)r; ++i) {
        if (d->cmd[i] == '\0') {
            d->cmd[i] = ' '; /* binary junk must not hide a newline from strchr */
        }
    }
    d->cmd_len += (size_t)r;
    d->cmd[d->cmd_len] = '\0';
    while ((nl = strchr(d->cmd, '\n')) != NULL) {
        const size_t used = (size_t)(nl - d->cmd) + 1u;
        *nl = '\0';
        if (nl > d->cmd && nl[-1] == '\r') {
            nl[-1] = '\0';
        }
        do_command(d, d->cmd);
        memmove(d->cmd, &d->cmd[used], d->cmd_len - used + 1u);
        d->cmd_len -= used;
    }
}

/* ------------------------------------------------------------------ main loop */
static void usage(void)
{
    fprintf(stderr, "usage: virtual_device [--rate HZ] [--ppm PPM] [--link PATH] [--signal sine|step] [--amplitude N]\n"
                    "       [--offset N] [--freq HZ] [--seq0 N] [--t0-us N] [--baud N] [--log FILE] [--seed N]\n"
                    "       [--duration S] [--serial TEXT] [--board TEXT] [--vref-uv N] [--gain N]\n"
                    "       [--status-period S] [--temp-period S] [--temperature C]\n"
                    "       (commands on stdin: see the source header or firmware/README.md)\n");
    exit(2);
}

int main(int argc, char **argv)
{
    static vdev_t dev;
    vdev_t *d = &dev;
    int i;
    struct sigaction sa;
    int64_t end_mono = 0;
    char serial[PFW_INFO_SERIAL_LEN + 1] = "VIRTUAL-0001";
    char board[PFW_INFO_BOARD_LEN + 1] = "virtual";

    memset(d, 0, sizeof *d);
    d->rate_hz = 1000u;
    d->amplitude = 4000000.0;
    d->offset = 100000.0;
    d->freq = 1.7;
    d->rng = 1u;
    d->master = -1;
    d->info.vref_uv = 5000000u;
    d->info.gain = 128u;
    d->info.adc_bits = 24u;
    d->info.mains_filter = PFW_MAINS_OFF;
    memcpy(d->info.adc, "virtual", 7u);
    d->status_period_s = 1.0;
    d->temp_period_s = 1.0;
    d->temperature_c = 25.0;
    d->reset_reason = PFW_RESET_POWER_ON;
    for (i = 1; i < argc; i += 2) { /* options come in pairs: --name value */
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        if (v == NULL) {
            usage();
        }
        if (strcmp(a, "--rate") == 0) {
            d->rate_hz = (uint32_t)strtoul(v, NULL, 0);
        } else if (strcmp(a, "--ppm") == 0) {
            d->ppm = strtod(v, NULL);
        } else if (strcmp(a, "--link") == 0) {
            d->link = v;
        } else if (strcmp(a, "--signal") == 0) {
            d->step_signal = strcmp(v, "step") == 0;
        } else if (strcmp(a, "--amplitude") == 0) {
            d->amplitude = strtod(v, NULL);
        } else if (strcmp(a, "--offset") == 0) {
            d->offset = strtod(v, NULL);
        } else if (strcmp(a, "--freq") == 0) {
            d->freq = strtod(v, NULL);
        } else if (strcmp(a, "--seq0") == 0) {
            d->seq0 = (uint16_t)strtoul(v, NULL, 0);
        } else if (strcmp(a, "--t0-us") == 0) {
            d->t0_us = (uint32_t)strtoul(v, NULL, 0);
        } else if (strcmp(a, "--baud") == 0) {
            d->baud = (uint32_t)strtoul(v, NULL, 0);
        } else if (strcmp(a, "--log") == 0) {
            d->log = fopen(v, "w");
            if (d->log == NULL) {
                fprintf(stderr, "virtual_device: %s: %s\n", v, strerror(errno));
                return 1;
            }
            setvbuf(d->log, NULL, _IOLBF, 0);
        } else if (strcmp(a, "--seed") == 0) {
            d->rng = strtoull(v, NULL, 0) | 1u;
        } else if (strcmp(a, "--duration") == 0) {
            d->duration_s = strtod(v, NULL);
        } else if (strcmp(a, "--serial") == 0) {
            snprintf(serial, sizeof serial, "%s", v);
        } else if (strcmp(a, "--board") == 0) {
            snprintf(board, sizeof board, "%s", v);
        } else if (strcmp(a, "--vref-uv") == 0) {
            d->info.vref_uv = (uint32_t)strtoul(v, NULL, 0);
        } else if (strcmp(a, "--gain") == 0) {
            d->info.gain = (uint16_t)strtoul(v, NULL, 0);
        } else if (strcmp(a, "--status-period") == 0) {
            d->status_period_s = strtod(v, NULL);
        } else if (strcmp(a, "--temp-period") == 0) {
            d->temp_period_s = strtod(v, NULL);
        } else if (strcmp(a, "--temperature") == 0) {
            d->temperature_c = strtod(v, NULL);
        } else {
            usage();
        }
    }
    if (d->rate_hz == 0u || d->rate_hz > PFW_MAX_RATE_HZ || fabs(d->ppm) > 100000.0 || d->info.gain == 0u) {
        usage();
    }
    memcpy(d->info.serial, serial, strlen(serial)); /* a full field has no terminating NUL */
    memcpy(d->info.board, board, strlen(board));

    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);
    fcntl(STDIN_FILENO, F_SETFL, fcntl(STDIN_FILENO, F_GETFL) | O_NONBLOCK);

    {
        const int64_t m1 = now_ns(CLOCK_MONOTONIC);
        const int64_t rt = now_ns(CLOCK_REALTIME);
        const int64_t m2 = now_ns(CLOCK_MONOTONIC);
        d->mono0_ns = m2;
        d->rt_minus_mono_ns = rt - (m1 + (m2 - m1) / 2);
    }
    d->ticks = 0u;
    d->tokens_ns = d->mono0_ns;
    if (d->duration_s > 0.0) {
        end_mono = d->mono0_ns + (int64_t)(d->duration_s * 1e9);
    }
    d->next_status_mono = d->mono0_ns + (int64_t)(d->status_period_s * 1e9);
    d->next_temp_mono = d->mono0_ns + (int64_t)(d->temp_period_s * 1e9);
    start_device_clock(d, d->t0_us, d->seq0);
    plug(d);

    while (!stop_requested) {
        struct pollfd fds[2];
        nfds_t nfds = 1u;
        int64_t mono = now_ns(CLOCK_MONOTONIC);
        int64_t wake;
        uint32_t now_us;
        int held;
        struct timespec timeout;

        if (end_mono != 0 && mono >= end_mono) {
            break;
        }
        /* the "hardware": the tick counter advances; the firmware reads it */
        d->ticks = ticks_at(d, mono);
        while (d->ticks - d->fed_ticks > 0x80000000u) { /* the 32-bit counter wraps every 4.3 s: */
            d->fed_ticks += 0x80000000u;                 /* a stopped process must not lose a wrap */
            (void)pfw_clock_update(&d->clock, (uint32_t)d->fed_ticks);
        }
        d->fed_ticks = d->ticks;
        now_us = pfw_clock_update(&d->clock, (uint32_t)d->ticks);
        if (now_us != (uint32_t)(d->us_origin + (uint32_t)((d->ticks - d->ticks_origin) / 1000u))) {
            fprintf(stderr, "virtual_device: core clock disagrees with the tick count\n");
            abort();
        }
        /* the firmware's periodic messages */
        if (d->status_period_s > 0.0 && mono >= d->next_status_mono) {
            d->status_pending = 1;
            d->next_status_mono = mono + (int64_t)(d->status_period_s * 1e9);
        }
        if (d->temp_period_s > 0.0 && mono >= d->next_temp_mono) {
            d->temp_pending = 1;
            d->next_temp_mono = mono + (int64_t)(d->temp_period_s * 1e9);
        }
        /* the "ADC interrupt": every conversion due so far, each drained at once so that a
           scheduling stall of this process does not overflow the ring by itself */
        held = 0;
        while (pfw_pacer_due(&d->pacer, now_us)) {
            const uint32_t due = pfw_pacer_advance(&d->pacer);
            if (d->reset_pending && d->out_pos == d->out_len) {
                /* device reset (at a frame boundary): RAM is lost, clock and sequence restart at 0 */
                d->reset_pending = 0;
                d->resets++;
                d->reset_reason = d->watchdog_pending ? PFW_RESET_WATCHDOG : PFW_RESET_EXTERNAL;
                if (d->watchdog_pending) {
                    d->watchdog_resets++;
                }
                log_line(d, "E %s %" PRId64 "\n", d->watchdog_pending ? "watchdog" : "reset", now_ns(CLOCK_REALTIME));
                d->watchdog_pending = 0;
                start_device_clock(d, 0u, 0u);
                now_us = pfw_clock_update(&d->clock, (uint32_t)d->ticks);
                continue;
            }
            (void)pfw_ring_record(&d->ring, due, sensor_counts(d, d->sample_index));
            d->sample_index++;
            held = pump(d, mono);
        }
        held = pump(d, mono);

        /* sleep until the next conversion, a command, or room on the wire */
        {
            /* the device clock reads next_us once (ticks - origin) reaches that many microseconds */
            const int32_t ahead_us = pfw_time_diff_us(d->pacer.next_us, now_us);
            const uint64_t elapsed_us = (d->ticks - d->ticks_origin) / 1000u + (uint64_t)(ahead_us > 0 ? ahead_us : 0);
            wake = mono_at_ticks(d, d->ticks_origin + elapsed_us * 1000u);
        }
        if (held && wake > mono + 500000) {
            wake = mono + 500000; /* baud-limited or full pty: check again in 0.5 ms */
        }
        if (d->status_period_s > 0.0 && wake > d->next_status_mono) {
            wake = d->next_status_mono;
        }
        if (d->temp_period_s > 0.0 && wake > d->next_temp_mono) {
            wake = d->next_temp_mono;
        }
        if (wake < mono) {
            wake = mono;
        }
        fds[0].fd = STDIN_FILENO;
        fds[0].events = POLLIN;
        fds[0].revents = 0;
        if (reader_present(d)) { /* with no reader the master reports POLLHUP at once: not polled then */
            fds[1].fd = d->master;
            fds[1].events = (short)(POLLIN | ((held && d->baud == 0u) ? POLLOUT : 0));
            fds[1].revents = 0;
            nfds = 2u;
        }
        timeout.tv_sec = (time_t)((wake - mono) / 1000000000);
        timeout.tv_nsec = (long)((wake - mono) % 1000000000);
        if (ppoll(fds, nfds, &timeout, NULL) > 0) {
            if ((fds[0].revents & (POLLIN | POLLHUP)) != 0) {
                read_commands(d);
            }
            if (nfds == 2u && (fds[1].revents & POLLIN) != 0) {
                read_requests(d);
            }
        }
    }
    if (d->master >= 0) {
        close(d->master);
    }
    if (d->link != NULL) {
        unlink(d->link);
    }
    if (d->log != NULL) {
        fclose(d->log);
    }
    return 0;
}
