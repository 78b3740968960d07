/*
 * board_ads1220_arduino.ino - polyforce bridge ADC: TI ADS1220 on an Arduino-compatible board.
 *
 * A thin shell over the portable core (polyforce_fw.h/.c, linked into this
 * folder from firmware/): the ADS1220 converts continuously at 1000 SPS with
 * the bridge excitation as its reference (ratiometric); its DRDY falling edge
 * interrupts; the interrupt stamps the conversion with the device clock, reads
 * the 24-bit result over SPI and records it in the ring; loop() pops frames and
 * writes them to the USB serial port. Wiring, driver parameters and the rate
 * budget: firmware/README.md.
 *
 * Tested boards are none (no hardware in CI); the sketch is compiled and run on
 * the PC against stub Arduino/SPI headers by test/test_firmware.py
 * (firmware/host/arduino_sim.cpp), which checks the register bytes, the SPI
 * read, the frames and the watchdog. Intended targets: 32-bit boards with
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
// Register 0: MUX = 0011 (AINP = AIN1, AINN = AIN2), GAIN = 111 (128), PGA_BYPASS = 0 (PGA on)
static const uint8_t ADS_REG0 = 0x3E;
// Register 1: DR = 110 (1000 SPS in normal mode), MODE = 00 (normal), CM = 1 (continuous), TS = 0, BCS = 0
static const uint8_t ADS_REG1 = 0xC4;
// Register 2: VREF = 01 (external REFP0/REFN0 = bridge excitation: ratiometric), 50/60 = 00, PSW = 0, IDAC = 000
static const uint8_t ADS_REG2 = 0x40;
// Register 3: I1MUX = I2MUX = 000 (IDACs off), DRDYM = 0 (DRDY on its own pin), reserved 0
static const uint8_t ADS_REG3 = 0x00;
static const uint32_t ADS_RATE_HZ = 1000;  // must match REG1 (and the driver's expected_rate_hz)
static const uint32_t ADS_SPI_HZ = 4000000;  // SCLK period 250 ns; the ADS1220 allows 150 ns
// SPI mode 1 (CPOL = 0, CPHA = 1): the ADS1220 latches DIN on the falling SCLK edge
static const SPISettings ADS_SPI(ADS_SPI_HZ, MSBFIRST, SPI_MODE1);
// No DRDY for this many sample periods (ADC reset by a brown-out, a loose wire): configure it again.
static const uint32_t WATCHDOG_PERIODS = 100;

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

// DRDY falling edge: one conversion is ready. The producer side of the ring.
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
    (void)pfw_ring_record(&g_ring, t_us, pfw_counts_from_be24(b2, b1, b0));  // full ring: counted, seq gap
    g_last_drdy_us = t_us;
}

void setup()
{
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

    SPI.usingInterrupt(digitalPinToInterrupt(PIN_ADS_DRDY));  // our own transactions mask DRDY
    ads_configure();
    attachInterrupt(digitalPinToInterrupt(PIN_ADS_DRDY), on_drdy, FALLING);
}

// The consumer side: frames out, as fast as the link takes them.
void loop()
{
    uint8_t frame[PFW_FRAME_SIZE];
    uint32_t now_us, last_us;
    while (pfw_ring_pop_frame(&g_ring, frame)) {
        LINK.write(frame, PFW_FRAME_SIZE);  // blocks while the link is busy; the ring absorbs it
    }
    // Keep the clock fed even without conversions (a 16-bit tick source must not miss a wrap),
    // and restart the ADC when DRDY has stopped.
    noInterrupts();
    now_us = pfw_clock_update(&g_clock, hw_ticks());
    last_us = g_last_drdy_us;
    interrupts();
    if (pfw_time_diff_us(now_us, last_us) > (int32_t)(WATCHDOG_PERIODS * g_period_us)) {
        ads_configure();
        noInterrupts();
        g_last_drdy_us = now_us;
        interrupts();
    }
}
