/* SPI.h - stub of the Arduino SPI library for running the polyforce sketch on a PC. */
#ifndef POLYFORCE_SPI_STUB_H
#define POLYFORCE_SPI_STUB_H

#include "Arduino.h"

#define SPI_MODE0 0x00
#define SPI_MODE1 0x04
#define SPI_MODE2 0x08
#define SPI_MODE3 0x0C

class SPISettings {
public:
    SPISettings() : clock(4000000), bit_order(MSBFIRST), mode(SPI_MODE0) {}
    SPISettings(uint32_t c, uint8_t order, uint8_t m) : clock(c), bit_order(order), mode(m) {}
    uint32_t clock;
    uint8_t bit_order;
    uint8_t mode;
};

class SPIClass {
public:
    void begin();
    void usingInterrupt(int interrupt);
    void beginTransaction(SPISettings settings);
    uint8_t transfer(uint8_t data);
    void endTransaction();
};
extern SPIClass SPI;

#endif
