/*
 * arduino_sim.cpp - runs board_ads1220_arduino.ino on a PC with a scripted ADS1220.
 *
 *   arduino_sim MICROS0 < script
 *
 * setup() runs first, then the script (one command per line):
 *   conv HEX6     one period (1000 us) passes, the ADC has the 24-bit word HEX6 ready: DRDY falls
 *                 (in temperature-sensor mode the ADC has the sensor's word instead, and HEX6 is unused)
 *   tempword HEX6 the 24-bit word of the temperature sensor from now on (default 0c8000: 25 degC)
 *   loop          loop() runs once
 *   advance US    time passes without conversions
 *   host HEX      the host writes these bytes to the serial port (e.g. 49 = 'I')
 *   reboot CODE   the board restarts with reset reason CODE (PFW_RESET_*): no-init RAM is kept,
 *                 setup() runs again
 * The scripted ADS1220 keeps its four configuration registers from the commands it receives (RESET,
 * WREG, START/SYNC): a conversion made while register 1 has TS set is a temperature conversion, and
 * the 50/60 Hz bits of register 2 are refused at any rate but 20 SPS normal / 5 SPS duty-cycle mode
 * (datasheet SBAS501, register 2).
 * Output: "spi AA BB .." (MOSI bytes of each SPI transaction), "isr MICROS" (micros() at each
 * DRDY; "isr MICROS ts" for a temperature conversion), "serial HEX" (all bytes the sketch wrote,
 * at the end), "baud N", "attach PIN MODE", "watchdog MS" (enabled), "watchdog expired" (not fed
 * for its period: the board would reset), and "error ..." for any misuse (transfer with CS high,
 * wrong SPI mode, unbalanced masking, 50/60 Hz rejection at a rate that does not allow it).
 */
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "Arduino.h"
#include "SPI.h"

void setup();
void loop();

static unsigned long long g_micros;
static bool g_cs_low = false;
static int g_masked = 0;
static int g_in_isr = 0;
static int g_cs_pin = -1;
static void (*g_isr)(void) = nullptr;
static std::vector<uint8_t> g_miso, g_mosi, g_serial;
static bool g_in_transaction = false;
static std::vector<uint8_t> g_rx;               // host -> device bytes not read yet
static uint8_t g_reset_reason = 1;              // PFW_RESET_POWER_ON
static uint16_t g_noinit[2] = {0x1234, 0x4321}; // random after power-on
static unsigned g_wd_ms = 0;                    // 0 = watchdog off
static unsigned long long g_wd_fed = 0;
static bool g_wd_expired = false;
static uint8_t g_ads_reg[4] = {0, 0, 0, 0};     // the ADS1220's configuration registers (reset values)
static unsigned long long g_temp_word = 0x0C8000; // the temperature sensor's conversion result

// The ADS1220's side of one SPI transaction: commands change its registers.
static void ads_receive(const std::vector<uint8_t> &mosi)
{
    for (size_t i = 0; i < mosi.size(); ++i) {
        const uint8_t b = mosi[i];
        if ((b & 0xFE) == 0x06) {  // RESET
            std::memset(g_ads_reg, 0, sizeof g_ads_reg);
        } else if ((b & 0xF0) == 0x40) {  // WREG 0100 rrnn: nn + 1 registers from rr
            const unsigned first = (b >> 2) & 3u, count = (b & 3u) + 1u;
            for (unsigned k = 0; k < count; ++k) {
                if (i + 1 >= mosi.size() || first + k > 3) {
                    std::printf("error WREG %02x without its data\n", b);
                    break;
                }
                g_ads_reg[first + k] = mosi[++i];
            }
        }  // START/SYNC (08) restarts the conversion; 00 clocks data out
    }
}

// 50/60 Hz rejection (register 2, bits 5:4) only with DR = 000 in normal or duty-cycle mode.
static void ads_check_mains()
{
    const bool mains = (g_ads_reg[2] & 0x30) != 0;
    const uint8_t dr_mode = g_ads_reg[1] & 0xF8;
    if (mains && dr_mode != 0x00 && dr_mode != 0x08) {
        std::printf("error 50/60 Hz rejection with register 1 = %02x (only 20 SPS normal, 5 SPS duty-cycle)\n",
                    g_ads_reg[1]);
    }
}

StubSerial Serial;
SPIClass SPI;

void pinMode(uint8_t pin, uint8_t mode)
{
    if (mode == OUTPUT && g_cs_pin < 0) {
        g_cs_pin = pin;  // the first output pin the sketch configures is CS
    }
}
void digitalWrite(uint8_t pin, uint8_t value)
{
    if ((int)pin == g_cs_pin) {
        g_cs_low = (value == LOW);
    }
}
int digitalRead(uint8_t) { return HIGH; }
unsigned long micros(void) { return (unsigned long)g_micros; }  // 64-bit on the PC; the sketch truncates
unsigned long millis(void) { return (unsigned long)(g_micros / 1000u); }
void delay(unsigned long ms) { g_micros += 1000ull * ms; }
void delayMicroseconds(unsigned int us) { g_micros += us; }
void noInterrupts(void) { g_masked++; }
void interrupts(void)
{
    if (--g_masked < 0) {
        std::printf("error interrupts() without noInterrupts()\n");
    }
}
int digitalPinToInterrupt(uint8_t pin) { return pin; }
void attachInterrupt(int interrupt, void (*isr)(void), int mode)
{
    g_isr = isr;
    std::printf("attach %d %s\n", interrupt, mode == FALLING ? "falling" : "other");
}

void StubSerial::begin(unsigned long baud) { std::printf("baud %lu\n", baud); }
int StubSerial::available() { return (int)g_rx.size(); }
int StubSerial::read()
{
    if (g_rx.empty()) {
        return -1;
    }
    const int b = g_rx.front();
    g_rx.erase(g_rx.begin());
    return b;
}

uint8_t stub_reset_reason(void) { return g_reset_reason; }
uint16_t *stub_noinit_u16(int index) { return &g_noinit[index]; }
void stub_watchdog_begin(unsigned ms)
{
    g_wd_ms = ms;
    g_wd_fed = g_micros;
    std::printf("watchdog %u\n", ms);
}
void stub_watchdog_feed(void) { g_wd_fed = g_micros; }

static void check_watchdog()
{
    if (g_wd_ms != 0 && !g_wd_expired && g_micros - g_wd_fed > 1000ull * g_wd_ms) {
        std::printf("watchdog expired\n");
        g_wd_expired = true;
    }
}
size_t StubSerial::write(const uint8_t *data, size_t len)
{
    if (g_in_isr) {
        std::printf("error Serial.write in the interrupt\n");
    }
    g_serial.insert(g_serial.end(), data, data + len);
    return len;
}

void SPIClass::begin() {}
void SPIClass::usingInterrupt(int) {}
void SPIClass::beginTransaction(SPISettings s)
{
    if (s.mode != SPI_MODE1 || s.bit_order != MSBFIRST || s.clock > 6000000u) {
        std::printf("error SPI settings mode=%d order=%d clock=%lu\n", s.mode, s.bit_order, (unsigned long)s.clock);
    }
    if (g_in_transaction) {
        std::printf("error nested SPI transaction\n");
    }
    g_in_transaction = true;
    g_mosi.clear();
}
uint8_t SPIClass::transfer(uint8_t data)
{
    if (!g_cs_low || !g_in_transaction) {
        std::printf("error SPI transfer with CS high or outside a transaction\n");
    }
    g_mosi.push_back(data);
    uint8_t out = 0xFF;
    if (!g_miso.empty()) {
        out = g_miso.front();
        g_miso.erase(g_miso.begin());
    }
    return out;
}
void SPIClass::endTransaction()
{
    std::printf("spi");
    for (uint8_t b : g_mosi) {
        std::printf(" %02x", b);
    }
    std::printf("\n");
    ads_receive(g_mosi);
    g_in_transaction = false;
}

int main(int argc, char **argv)
{
    g_micros = (argc > 1) ? std::strtoull(argv[1], nullptr, 0) : 0u;
    setup();
    char line[256];
    while (std::fgets(line, sizeof line, stdin) != nullptr) {
        char cmd[32] = "";
        unsigned long long arg = 0;
        int n = std::sscanf(line, "%31s %llx", cmd, &arg);
        if (n < 1) {
            continue;
        }
        if (std::strcmp(cmd, "conv") == 0 && n == 2) {
            g_micros += 1000u;
            const bool ts = (g_ads_reg[1] & 0x02) != 0;  // set before this conversion started
            if (ts) {
                arg = g_temp_word;
            }
            g_miso = {uint8_t(arg >> 16), uint8_t(arg >> 8), uint8_t(arg)};
            if (g_isr == nullptr || g_masked) {
                std::printf("error DRDY with no handler or interrupts masked\n");
                continue;
            }
            ads_check_mains();
            std::printf("isr %llu%s\n", g_micros, ts ? " ts" : "");
            g_in_isr = 1;
            g_isr();
            g_in_isr = 0;
            if (!g_miso.empty()) {
                std::printf("error conversion not read\n");
            }
        } else if (std::strcmp(cmd, "tempword") == 0 && n == 2) {
            g_temp_word = arg;
        } else if (std::strcmp(cmd, "loop") == 0) {
            loop();
        } else if (std::strcmp(cmd, "advance") == 0) {
            std::sscanf(line, "%31s %llu", cmd, &arg);
            g_micros += arg;
        } else if (std::strcmp(cmd, "host") == 0) {
            const char *hex = line + 4;
            unsigned byte;
            int used;
            while (std::sscanf(hex, " %2x%n", &byte, &used) == 1) {
                g_rx.push_back((uint8_t)byte);
                hex += used;
            }
        } else if (std::strcmp(cmd, "reboot") == 0) {
            std::sscanf(line, "%31s %llu", cmd, &arg);
            g_reset_reason = (uint8_t)arg;
            g_isr = nullptr;
            g_wd_ms = 0;
            g_wd_expired = false;
            g_rx.clear();
            std::memset(g_ads_reg, 0, sizeof g_ads_reg);  // the ADS1220 restarts with the board (same supply)
            setup();
        }
        check_watchdog();
    }
    if (g_masked != 0) {
        std::printf("error interrupts left masked\n");
    }
    std::printf("serial ");
    for (uint8_t b : g_serial) {
        std::printf("%02x", b);
    }
    std::printf("\n");
    return 0;
}
