/*
 * board_ads1220_arduino.ino - polyforce bridge ADC: TI ADS1220 on an Arduino-compatible board.
 *
 * A thin shell over the portable core (polyforce_fw.h/.c, linked into this
 * folder from firmware/): the ADS1220 converts continuously at 1000 SPS (20 SPS
 * with simultaneous 50/60 Hz rejection when built with PFW_MAINS_REJECTION=1)
 * with the bridge excitation as its reference (ratiometric); its DRDY falling
 * edge interrupts; the interrupt stamps the conversion with the device clock,
 * reads the 24-bit result over SPI and records it in the ring; loop() pops
 * frames and writes them to the USB serial port. Once a second (every 10 s with
 * mains rejection) the interrupt switches the ADC to its internal temperature
 * sensor for one conversion and back; that conversion becomes a temperature
 * message, never a sample. Between frames loop() sends the messages of
 * polyforce_fw.h: info at start and when the host writes 'I', status at start,
 * every second and when the host writes 'S', and the temperature. Where the
 * board has a watchdog hook below (AVR, SAMD21, RP2040), loop() feeds it only
 * while conversions arrive, and the status reports why the board last started.
 * Wiring, driver parameters and the rate budget: firmware/README.md.
 *
 * Tested boards are none (no hardware in CI); the sketch is compiled and run on
 * the PC against stub Arduino/SPI headers by test/test_firmware.py
 * (firmware/host/arduino_sim.cpp), which checks the register bytes, the SPI
 * read, the frames, the temperature conversions, the mains-rejection
 * configuration and the watchdog. Intended targets: 32-bit boards with
 * native USB (Arduino Zero/MKR, Teensy 3.x/4.x, RP2040 boards) — USB CDC is not
 * limited by a baud rate; a hardware UART must run at >= 230400 baud (README).
 */
#include <SPI.h>

#include "polyforce_fw.h"

// ---------------------------------------------------------------- pins (README wiring table)
static const uint8_t PIN_ADS_CS = 10;   // ADS1220 CS (active low)
static const uint8_t PIN_ADS_DRDY = 2;  // ADS1220 DRDY (active low, push-pull): an interrupt-capable pin
// SCLK, DIN, DOUT: the board's hardware SPI pins (SCK, MOSI, MISO).

// ---------------------------------------------------------------- link
#define LINK Serial                      // native USB CDC on Zero (SerialUSB there), MKR, Teensy, RP2040
static const uint32_t LINK_BAUD = 921600; // ignored by USB CDC; used by hardware UARTs (driver default)

// ---------------------------------------------------------------- ADS1220 (datasheet SBAS501, section 8.6)
static const uint8_t ADS_CMD_RESET = 0x06;
static const uint8_t ADS_CMD_START = 0x08;
static const uint8_t ADS_CMD_WREG_0_4 = 0x43;  // WREG from register 0, 4 registers (0100 rrnn: rr = 0, nn = 3)
static const uint8_t ADS_CMD_WREG_1_1 = 0x44;  // WREG register 1 only (rr = 1, nn = 0)
// Register 0: MUX = 0011 (AINP = AIN1, AINN = AIN2), GAIN = 111 (128), PGA_BYPASS = 0 (PGA on)
static const uint8_t ADS_REG0 = 0x3E;
// 50/60 Hz rejection (register 2, bits 5:4) is allowed only at 20 SPS in normal mode (and 5 SPS in
// duty-cycle mode): build with -DPFW_MAINS_REJECTION=1 for 20 SPS with simultaneous 50 and 60 Hz
// rejection, or keep the default 1000 SPS with no mains filter. Trade-off: docs/firmware.md.
#ifndef PFW_MAINS_REJECTION
#define PFW_MAINS_REJECTION 0
#endif
#if PFW_MAINS_REJECTION
// Register 1: DR = 000 (20 SPS in normal mode), MODE = 00 (normal), CM = 1 (continuous), TS = 0, BCS = 0
static const uint8_t ADS_REG1 = 0x04;
// Register 2: VREF = 01 (external REFP0/REFN0 = bridge excitation: ratiometric), 50/60 = 01
// (simultaneous 50 and 60 Hz rejection), PSW = 0, IDAC = 000
static const uint8_t ADS_REG2 = 0x50;
static const uint32_t ADS_RATE_HZ = 20;
static const uint8_t ADS_MAINS_FILTER = PFW_MAINS_50_60;
#else
// Register 1: DR = 110 (1000 SPS in normal mode), MODE = 00 (normal), CM = 1 (continuous), TS = 0, BCS = 0
static const uint8_t ADS_REG1 = 0xC4;
// Register 2: VREF = 01 (external REFP0/REFN0 = bridge excitation: ratiometric), 50/60 = 00, PSW = 0, IDAC = 000
static const uint8_t ADS_REG2 = 0x40;
static const uint32_t ADS_RATE_HZ = 1000;  // must match REG1 (and the driver's expected_rate_hz)
static const uint8_t ADS_MAINS_FILTER = PFW_MAINS_OFF;
#endif
// Register 1, TS = 1: the internal temperature sensor instead of the inputs (register 0 has no effect)
static const uint8_t ADS_REG1_TS = 0x02;
// Register 3: I1MUX = I2MUX = 000 (IDACs off), DRDYM = 0 (DRDY on its own pin), reserved 0
static const uint8_t ADS_REG3 = 0x00;
static const uint32_t ADS_VREF_UV = 5000000;  // the reference = bridge excitation (uV): reported in the info
static const uint16_t ADS_GAIN = 128;         // must match REG0
static const uint32_t ADS_SPI_HZ = 4000000;  // SCLK period 250 ns; the ADS1220 allows 150 ns
// SPI mode 1 (CPOL = 0, CPHA = 1): the ADS1220 latches DIN on the falling SCLK edge
static const SPISettings ADS_SPI(ADS_SPI_HZ, MSBFIRST, SPI_MODE1);
// No DRDY for this many sample periods (ADC reset by a brown-out, a loose wire): configure it again.
static const uint32_t WATCHDOG_PERIODS = 100;

// ---------------------------------------------------------------- identity (info message)
// The serial number of the sensor wired to this board: set it when flashing, so that the host can
// tie a calibrated model to this sensor (arduino-cli compile --build-property
// "compiler.cpp.extra_flags=-DSENSOR_SERIAL=\"PF-0042\"").
#ifndef SENSOR_SERIAL
#define SENSOR_SERIAL "unset"
#endif
#if defined(ARDUINO_SAMD_ZERO)
#define BOARD_NAME "arduino-zero"
#elif defined(ARDUINO_SAMD_MKRZERO) || defined(ARDUINO_SAMD_MKR1000) || defined(ARDUINO_SAMD_MKRWIFI1010)
#define BOARD_NAME "arduino-mkr"
#elif defined(ARDUINO_ARCH_RP2040)
#define BOARD_NAME "rp2040"
#elif defined(TEENSYDUINO)
#define BOARD_NAME "teensy"
#elif defined(ARDUINO_AVR_UNO) || defined(ARDUINO_AVR_NANO)
#define BOARD_NAME "avr-uno-nano"
#else
#define BOARD_NAME "arduino"
#endif
static const uint32_t STATUS_PERIOD_US = 1000000;  // a status message every second
// A temperature conversion takes the place of about one bridge sample (plus the restart after each
// switch): once a second at 1000 SPS (0.1 % of the samples), every 10 s at 20 SPS (0.5 %).
static const uint32_t TEMP_PERIOD_US = PFW_MAINS_REJECTION ? 10000000 : 1000000;

// ---------------------------------------------------------------- MCU watchdog and reset reason
// The watchdog is fed by loop() only while conversions arrive (or the ADC is being configured
// again): a hang in the link write, a hard fault or a dead loop resets the board. Its period,
// 1 s, is longer than the ring's 256 ms: a link that stalls for less costs frames (counted as
// overflows), not a reset. Hooks exist for AVR, SAMD21 (Zero, MKR), RP2040 (arduino-pico) and the
// PC stubs; on other cores (Teensy, SAMD51, ESP32) there is none and the reset reason is "unknown".
// Only the AVR hook keeps the watchdog-reset count across resets (no-init RAM); see README.
static const unsigned WATCHDOG_MS = 1000;
#if defined(__AVR__)
#include <avr/wdt.h>
static uint8_t g_mcusr __attribute__((section(".noinit")));  // MCUSR as the bootloader or reset left it
static uint16_t g_wd_resets __attribute__((section(".noinit")));
static uint16_t g_wd_magic __attribute__((section(".noinit")));
static uint8_t board_reset_reason()
{
    g_mcusr = MCUSR;
    MCUSR = 0;
    if (g_mcusr & _BV(WDRF)) return PFW_RESET_WATCHDOG;
    if (g_mcusr & _BV(BORF)) return PFW_RESET_BROWN_OUT;
    if (g_mcusr & _BV(EXTRF)) return PFW_RESET_EXTERNAL;
    if (g_mcusr & _BV(PORF)) return PFW_RESET_POWER_ON;
    return PFW_RESET_UNKNOWN;  // optiboot clears MCUSR before the sketch runs
}
static uint16_t *board_watchdog_count() { return &g_wd_resets; }  // survives a reset, not a power-on
static uint16_t *board_watchdog_magic() { return &g_wd_magic; }
static void board_watchdog_begin() { wdt_enable(WDTO_1S); }
static void board_watchdog_feed() { wdt_reset(); }
#elif defined(ARDUINO_ARCH_SAMD) && !defined(__SAMD51__)
// SAMD21 (arduino:samd core, CMSIS register names). The core's linker script has no no-init
// section, so the count lives in .bss: after a watchdog reset it is 1, not the count since power-on.
static uint16_t g_wd_resets;
static uint16_t g_wd_magic;
static uint8_t board_reset_reason()
{
    const uint8_t rcause = PM->RCAUSE.reg;  // the cause of the last reset (the bootloader keeps it)
    if (rcause & PM_RCAUSE_WDT) return PFW_RESET_WATCHDOG;
    if (rcause & PM_RCAUSE_SYST) return PFW_RESET_SOFTWARE;  // NVIC_SystemReset, e.g. the 1200-baud upload touch
    if (rcause & PM_RCAUSE_EXT) return PFW_RESET_EXTERNAL;
    if (rcause & PM_RCAUSE_POR) return PFW_RESET_POWER_ON;
    if (rcause & (PM_RCAUSE_BOD12 | PM_RCAUSE_BOD33)) return PFW_RESET_BROWN_OUT;
    return PFW_RESET_UNKNOWN;
}
static uint16_t *board_watchdog_count() { return &g_wd_resets; }
static uint16_t *board_watchdog_magic() { return &g_wd_magic; }
static void board_watchdog_begin()
{
    // The WDT's clock: generator 2 = OSCULP32K / 2^(4 + 1) = 1024 Hz; 1024 cycles = 1 s (WATCHDOG_MS)
    GCLK->GENDIV.reg = GCLK_GENDIV_ID(2) | GCLK_GENDIV_DIV(4);
    GCLK->GENCTRL.reg = GCLK_GENCTRL_ID(2) | GCLK_GENCTRL_GENEN | GCLK_GENCTRL_SRC_OSCULP32K | GCLK_GENCTRL_DIVSEL;
    while (GCLK->STATUS.bit.SYNCBUSY) {
    }
    GCLK->CLKCTRL.reg = GCLK_CLKCTRL_ID_WDT | GCLK_CLKCTRL_CLKEN | GCLK_CLKCTRL_GEN_GCLK2;
    WDT->CTRL.reg = 0;
    while (WDT->STATUS.bit.SYNCBUSY) {
    }
    WDT->CONFIG.reg = WDT_CONFIG_PER_1K;
    WDT->CTRL.reg = WDT_CTRL_ENABLE;
    while (WDT->STATUS.bit.SYNCBUSY) {
    }
}
static void board_watchdog_feed()
{
    // A clear takes a few WDT clock cycles (ms) to synchronise; one still under way is a feed already,
    // and waiting for it would stall the 1 kHz loop.
    if (!WDT->STATUS.bit.SYNCBUSY) {
        WDT->CLEAR.reg = WDT_CLEAR_CLEAR_KEY;
    }
}
#elif defined(ARDUINO_ARCH_RP2040) && !defined(ARDUINO_ARCH_MBED)
// RP2040 with the arduino-pico core: the pico SDK's watchdog. The count lives in the SDK's
// uninitialized RAM section, which a watchdog reset leaves as it was.
#include <hardware/watchdog.h>
#if !defined(PICO_RP2350)
#include <hardware/structs/vreg_and_chip_reset.h>
#endif
static uint16_t __uninitialized_ram(g_wd_resets);
static uint16_t __uninitialized_ram(g_wd_magic);
static uint8_t board_reset_reason()
{
    if (watchdog_enable_caused_reboot()) return PFW_RESET_WATCHDOG;  // our watchdog_enable() ran out
    if (watchdog_caused_reboot()) return PFW_RESET_SOFTWARE;          // watchdog_reboot(): upload, rp2040.reboot()
#if !defined(PICO_RP2350)
    const uint32_t chip_reset = vreg_and_chip_reset_hw->chip_reset;
    if (chip_reset & VREG_AND_CHIP_RESET_CHIP_RESET_HAD_RUN_BITS) return PFW_RESET_EXTERNAL;  // RUN pin
    if (chip_reset & VREG_AND_CHIP_RESET_CHIP_RESET_HAD_POR_BITS) return PFW_RESET_POWER_ON;  // or brown-out
#endif
    return PFW_RESET_UNKNOWN;
}
static uint16_t *board_watchdog_count() { return &g_wd_resets; }
static uint16_t *board_watchdog_magic() { return &g_wd_magic; }
static void board_watchdog_begin() { watchdog_enable(WATCHDOG_MS, true); }  // paused while a debugger halts
static void board_watchdog_feed() { watchdog_update(); }
#elif defined(POLYFORCE_HOST_STUB)
static uint8_t board_reset_reason() { return stub_reset_reason(); }
static uint16_t *board_watchdog_count() { return stub_noinit_u16(0); }
static uint16_t *board_watchdog_magic() { return stub_noinit_u16(1); }
static void board_watchdog_begin() { stub_watchdog_begin(WATCHDOG_MS); }
static void board_watchdog_feed() { stub_watchdog_feed(); }
#else
static uint16_t g_wd_resets_none = 0;
static uint16_t g_wd_magic_none = 0;
static uint8_t board_reset_reason() { return PFW_RESET_UNKNOWN; }
static uint16_t *board_watchdog_count() { return &g_wd_resets_none; }
static uint16_t *board_watchdog_magic() { return &g_wd_magic_none; }
static void board_watchdog_begin() {}
static void board_watchdog_feed() {}
#endif
static const uint16_t WD_MAGIC = 0x5AFE;  // the no-init counter is valid only after this was written

// ---------------------------------------------------------------- device clock source
// Any free-running hardware counter works (pfw_clock_init takes its frequency and width).
// Default: the core's micros(), which every Arduino core derives from a hardware timer, 32 bits,
// 1 MHz. A raw timer can replace it, e.g. the Cortex-M3/M4/M7 cycle counter (Teensy:
// ARM_DWT_CYCCNT at F_CPU_ACTUAL, 32 bits) — pfw_clock carries the remainder, so it never drifts.
static inline uint32_t hw_ticks() { return (uint32_t)micros(); }
static const uint32_t HW_TICK_HZ = 1000000;
static const uint32_t HW_TICK_BITS = 32;

// ---------------------------------------------------------------- state
static pfw_ring_t g_ring;                 // DRDY interrupt -> loop()
static pfw_clock_t g_clock;               // updated by the interrupt, and by loop() with interrupts masked
static volatile uint32_t g_last_drdy_us;  // device time of the last conversion (interrupt writes)
static uint32_t g_period_us;
static pfw_info_t g_info;
static uint8_t g_reset_reason;
static uint32_t g_adc_reconfigs;   // DRDY fell silent and the ADC was configured again
static uint32_t g_start_us;        // device time at the end of setup()
static uint32_t g_next_status_us;  // device time of the next periodic status
static uint32_t g_uptime_s;        // whole seconds since setup(), counted from the periodic status
static uint32_t g_next_temp_us;    // device time of the next temperature request
// The temperature sensor. loop() sets g_temp_wanted; the interrupt, right after reading a bridge
// sample, switches the ADC to TS and sets g_temp_converting; the next conversion is the temperature,
// which the interrupt decodes into g_temp_q5 / g_temp_t_us (then g_temp_ready) before switching back.
static volatile bool g_temp_wanted;
static volatile bool g_temp_converting;
static volatile bool g_temp_ready;
static volatile int16_t g_temp_q5;     // 1/32 degC
static volatile uint32_t g_temp_t_us;  // device time of the temperature conversion

static void ads_command(uint8_t cmd)
{
    SPI.beginTransaction(ADS_SPI);  // masks the DRDY interrupt (SPI.usingInterrupt below)
    digitalWrite(PIN_ADS_CS, LOW);
    SPI.transfer(cmd);
    digitalWrite(PIN_ADS_CS, HIGH);
    SPI.endTransaction();
}

static void ads_configure()
{
    ads_command(ADS_CMD_RESET);
    delay(1);  // >= 50 us + 32 clock periods after RESET
    SPI.beginTransaction(ADS_SPI);
    digitalWrite(PIN_ADS_CS, LOW);
    SPI.transfer(ADS_CMD_WREG_0_4);
    SPI.transfer(ADS_REG0);
    SPI.transfer(ADS_REG1);
    SPI.transfer(ADS_REG2);
    SPI.transfer(ADS_REG3);
    digitalWrite(PIN_ADS_CS, HIGH);
    SPI.endTransaction();
    ads_command(ADS_CMD_START);  // continuous mode: converts until the next RESET/POWERDOWN
}

// Register 1 alone, then START/SYNC. A register write restarts the conversion in progress with the
// new setting (datasheet, continuous conversion mode); START/SYNC restarts it once more, as the
// datasheet recommends after writing CM = 1. The next DRDY is the first conversion in the new mode.
static void ads_write_reg1(uint8_t value)
{
    SPI.beginTransaction(ADS_SPI);
    digitalWrite(PIN_ADS_CS, LOW);
    SPI.transfer(ADS_CMD_WREG_1_1);
    SPI.transfer(value);
    digitalWrite(PIN_ADS_CS, HIGH);
    SPI.endTransaction();
    ads_command(ADS_CMD_START);
}

// The device clock, read from loop() (the interrupt updates it too).
static uint32_t clock_now_masked()
{
    noInterrupts();
    const uint32_t now_us = pfw_clock_update(&g_clock, hw_ticks());
    interrupts();
    return now_us;
}

// DRDY falling edge: one conversion is ready. The producer side of the ring. A temperature
// conversion is never recorded as a sample; its sequence number is not taken either, so the host
// sees a longer step of t_us between two consecutive samples, not a sequence gap.
static void on_drdy()
{
    const uint32_t t_us = pfw_clock_update(&g_clock, hw_ticks());
    uint8_t b2, b1, b0;
    SPI.beginTransaction(ADS_SPI);
    digitalWrite(PIN_ADS_CS, LOW);
    b2 = SPI.transfer(0x00);  // continuous mode: 24 SCLKs read the result directly (no RDATA)
    b1 = SPI.transfer(0x00);
    b0 = SPI.transfer(0x00);
    digitalWrite(PIN_ADS_CS, HIGH);
    SPI.endTransaction();
    if (g_temp_converting) {
        g_temp_q5 = pfw_ads1220_temp_q5(b2, b1);  // 14 bits, left-justified
        g_temp_t_us = t_us;
        g_temp_ready = true;
        g_temp_converting = false;
        ads_write_reg1(ADS_REG1);  // back to the bridge
    } else {
        (void)pfw_ring_record(&g_ring, t_us, pfw_counts_from_be24(b2, b1, b0));  // full ring: counted, seq gap
        if (g_temp_wanted) {
            g_temp_wanted = false;
            g_temp_converting = true;
            ads_write_reg1((uint8_t)(ADS_REG1 | ADS_REG1_TS));  // the next conversion: the temperature
        }
    }
    g_last_drdy_us = t_us;
}

static void copy_text(char *dst, const char *src, size_t size)
{
    for (size_t i = 0; i < size && src[i] != '\0'; ++i) {
        dst[i] = src[i];
    }
}

static void send_info()
{
    uint8_t msg[PFW_MSG_MAX_SIZE];
    LINK.write(msg, pfw_encode_info(msg, &g_info));
}

static void send_status(uint32_t now_us)
{
    uint8_t msg[PFW_MSG_MAX_SIZE];
    pfw_status_t st;
    st.t_us = now_us;
    st.reset_reason = g_reset_reason;
    st.watchdog_resets = *board_watchdog_count();
    noInterrupts();  // a 32-bit load is not atomic on AVR
    st.overflows = g_ring.overflows;
    interrupts();
    st.adc_reconfigs = g_adc_reconfigs;
    st.uptime_s = g_uptime_s;
    LINK.write(msg, pfw_encode_status(msg, &st));
}

void setup()
{
    g_adc_reconfigs = 0;
    g_uptime_s = 0;
    g_temp_wanted = false;
    g_temp_converting = false;
    g_temp_ready = false;
    g_reset_reason = board_reset_reason();
    if (*board_watchdog_magic() != WD_MAGIC || g_reset_reason == PFW_RESET_POWER_ON) {
        *board_watchdog_magic() = WD_MAGIC;  // RAM content is random after power-on
        *board_watchdog_count() = 0;
    }
    if (g_reset_reason == PFW_RESET_WATCHDOG) {
        *board_watchdog_count() = (uint16_t)(*board_watchdog_count() + 1);
    }
    LINK.begin(LINK_BAUD);
    pinMode(PIN_ADS_CS, OUTPUT);
    digitalWrite(PIN_ADS_CS, HIGH);
    pinMode(PIN_ADS_DRDY, INPUT);
    SPI.begin();
    delay(10);  // ADS1220 power-up

    pfw_ring_init(&g_ring, 0);
    g_period_us = pfw_period_us(ADS_RATE_HZ);
    (void)pfw_clock_init(&g_clock, HW_TICK_HZ, HW_TICK_BITS, hw_ticks(), 0);  // device clock starts at 0
    g_last_drdy_us = 0;

    g_info.rate_hz = ADS_RATE_HZ;
    g_info.vref_uv = ADS_VREF_UV;
    g_info.gain = ADS_GAIN;
    g_info.adc_bits = 24;
    g_info.mains_filter = ADS_MAINS_FILTER;  // REG2 bits 5:4
    copy_text(g_info.adc, "ADS1220", sizeof g_info.adc);
    copy_text(g_info.board, BOARD_NAME, sizeof g_info.board);
    copy_text(g_info.serial, SENSOR_SERIAL, sizeof g_info.serial);

    SPI.usingInterrupt(digitalPinToInterrupt(PIN_ADS_DRDY));  // our own transactions mask DRDY
    ads_configure();
    attachInterrupt(digitalPinToInterrupt(PIN_ADS_DRDY), on_drdy, FALLING);
    send_info();  // who this is, and why it started
    g_start_us = pfw_clock_update(&g_clock, hw_ticks());
    send_status(g_start_us);
    g_next_status_us = g_start_us + STATUS_PERIOD_US;
    g_next_temp_us = g_start_us + TEMP_PERIOD_US;
    board_watchdog_begin();
}

// The consumer side: frames out, as fast as the link takes them.
void loop()
{
    uint8_t frame[PFW_FRAME_SIZE];
    uint32_t now_us, last_us;
    while (pfw_ring_pop_frame(&g_ring, frame)) {
        LINK.write(frame, PFW_FRAME_SIZE);  // blocks while the link is busy; the ring absorbs it
    }
    while (LINK.available() > 0) {  // the host's requests
        const int request = LINK.read();
        if (request == (int)PFW_REQUEST_INFO) {
            send_info();
        } else if (request == (int)PFW_REQUEST_STATUS) {
            send_status(clock_now_masked());
        }
    }
    // Keep the clock fed even without conversions (a 16-bit tick source must not miss a wrap),
    // and restart the ADC when DRDY has stopped.
    noInterrupts();
    now_us = pfw_clock_update(&g_clock, hw_ticks());
    last_us = g_last_drdy_us;
    interrupts();
    if (pfw_time_diff_us(now_us, last_us) > (int32_t)(WATCHDOG_PERIODS * g_period_us)) {
        noInterrupts();
        if (g_temp_converting) {  // the configuration below clears TS: ask for the lost temperature again
            g_temp_converting = false;
            g_temp_wanted = true;
        }
        interrupts();
        ads_configure();
        g_adc_reconfigs++;
        noInterrupts();
        g_last_drdy_us = now_us;
        interrupts();
    } else {
        board_watchdog_feed();  // conversions arrive (or the ADC was just configured again): healthy
    }
    if (pfw_time_diff_us(now_us, g_next_status_us) >= 0) {
        g_next_status_us += STATUS_PERIOD_US;
        g_uptime_s++;
        send_status(now_us);
    }
    if (pfw_time_diff_us(now_us, g_next_temp_us) >= 0) {
        g_next_temp_us += TEMP_PERIOD_US;
        g_temp_wanted = true;  // taken by the interrupt after the next bridge sample
    }
    noInterrupts();
    const bool temp_ready = g_temp_ready;
    const int16_t temp_q5 = g_temp_q5;
    const uint32_t temp_t_us = g_temp_t_us;
    g_temp_ready = false;
    interrupts();
    if (temp_ready) {
        uint8_t msg[PFW_MSG_MAX_SIZE];
        LINK.write(msg, pfw_encode_temperature(msg, temp_t_us, temp_q5));
    }
}
