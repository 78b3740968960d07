/* Arduino.h - the few Arduino core functions the polyforce sketch uses, for compiling and
 * running it on a PC (firmware/host/arduino_sim.cpp implements them). Not a general emulator. */
#ifndef POLYFORCE_ARDUINO_STUB_H
#define POLYFORCE_ARDUINO_STUB_H

#include <stddef.h>
#include <stdint.h>

#define HIGH 0x1
#define LOW 0x0
#define INPUT 0x0
#define OUTPUT 0x1
#define INPUT_PULLUP 0x2
#define FALLING 2
#define MSBFIRST 1

void pinMode(uint8_t pin, uint8_t mode);
void digitalWrite(uint8_t pin, uint8_t value);
int digitalRead(uint8_t pin);
unsigned long micros(void);
unsigned long millis(void);
void delay(unsigned long ms);
void delayMicroseconds(unsigned int us);
void noInterrupts(void);
void interrupts(void);
int digitalPinToInterrupt(uint8_t pin);
void attachInterrupt(int interrupt, void (*isr)(void), int mode);

/* The sketch's board hooks on the PC (arduino_sim.cpp): reset reason, no-init RAM, watchdog. */
#define POLYFORCE_HOST_STUB 1
uint8_t stub_reset_reason(void);
uint16_t *stub_noinit_u16(int index);
void stub_watchdog_begin(unsigned ms);
void stub_watchdog_feed(void);

class StubSerial {
public:
    void begin(unsigned long baud);
    int available();
    int read();
    size_t write(const uint8_t *data, size_t len);
    size_t write(uint8_t byte) { return write(&byte, 1); }
    operator bool() const { return true; }
};
extern StubSerial Serial;

#endif
