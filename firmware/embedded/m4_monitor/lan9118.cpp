#include "lan9118.hpp"

#include <cstring>

namespace rockwatch::m4 {

namespace {

// Register offsets (SMSC LAN9118 data sheet, "System Control and Status Registers").
constexpr std::uint32_t kRxData = 0x00, kTxData = 0x20, kRxStatus = 0x40, kTxStatus = 0x48, kIdRev = 0x50,
                        kIrqCfg = 0x54, kIntSts = 0x58, kIntEn = 0x5c, kByteTest = 0x64, kFifoInt = 0x68,
                        kRxCfg = 0x6c, kTxCfg = 0x70, kHwCfg = 0x74, kRxFifoInf = 0x7c, kTxFifoInf = 0x80,
                        kPmtCtrl = 0x84, kMacCsrCmd = 0xa4, kMacCsrData = 0xa8;
// MAC control and status registers (indirect, through MAC_CSR_CMD/DATA).
constexpr std::uint32_t kMacCr = 1, kMacAddrH = 2, kMacAddrL = 3;
constexpr std::uint32_t kMacCrRxEn = 1u << 2, kMacCrTxEn = 1u << 3, kMacCrFullDuplex = 1u << 20,
                        kMacCrPassAllMulticast = 1u << 19;
constexpr std::uint32_t kCsrBusy = 1u << 31, kCsrRead = 1u << 30;
constexpr std::uint32_t kIntRsfl = 1u << 3;         // RX status FIFO level
constexpr std::uint32_t kIrqEn = 1u << 8, kIrqPol = 1u << 4, kIrqType = 1u << 0;  // active high, push-pull
constexpr std::uint32_t kRxStatusError = 1u << 15;  // error summary
constexpr std::uint32_t kRxDump = 1u << 15;
constexpr std::uint32_t kTxOn = 1u << 1;
constexpr std::uint32_t kTxFirst = 1u << 13, kTxLast = 1u << 12;

volatile std::uint32_t& nvic_iser0() { return *reinterpret_cast<volatile std::uint32_t*>(std::uintptr_t{0xE000E100}); }
volatile std::uint32_t& nvic_icpr0() { return *reinterpret_cast<volatile std::uint32_t*>(std::uintptr_t{0xE000E280}); }

// A read whose value is not needed (popping a FIFO entry).
inline void discard(std::uint32_t) {}

}  // namespace

void Lan9118::mac_write(std::uint32_t index, std::uint32_t value) {
  for (int i = 0; i < 1000 && (reg(kMacCsrCmd) & kCsrBusy) != 0; ++i) {
  }
  reg(kMacCsrData) = value;
  reg(kMacCsrCmd) = kCsrBusy | index;
}

std::uint32_t Lan9118::mac_read(std::uint32_t index) {
  for (int i = 0; i < 1000 && (reg(kMacCsrCmd) & kCsrBusy) != 0; ++i) {
  }
  reg(kMacCsrCmd) = kCsrBusy | kCsrRead | index;
  for (int i = 0; i < 1000 && (reg(kMacCsrCmd) & kCsrBusy) != 0; ++i) {
  }
  return reg(kMacCsrData);
}

bool Lan9118::init(const std::uint8_t mac[6]) {
  if (reg(kByteTest) != 0x87654321u || (reg(kIdRev) >> 16) != 0x0118u) return false;
  reg(kHwCfg) = 1;  // soft reset
  for (int i = 0; i < 100000 && (reg(kHwCfg) & 1) != 0; ++i) {
  }
  for (int i = 0; i < 100000 && (reg(kPmtCtrl) & 1) == 0; ++i) {  // READY
  }
  mac_write(kMacAddrL, std::uint32_t{mac[0]} | std::uint32_t{mac[1]} << 8 | std::uint32_t{mac[2]} << 16 |
                           std::uint32_t{mac[3]} << 24);
  mac_write(kMacAddrH, std::uint32_t{mac[4]} | std::uint32_t{mac[5]} << 8);
  mac_write(kMacCr, kMacCrRxEn | kMacCrTxEn | kMacCrFullDuplex | kMacCrPassAllMulticast);
  if ((mac_read(kMacCr) & (kMacCrRxEn | kMacCrTxEn)) != (kMacCrRxEn | kMacCrTxEn)) return false;
  reg(kRxCfg) = kRxDump;  // empty FIFOs, no offset, no end padding
  reg(kTxCfg) = kTxOn;
  reg(kFifoInt) = 0;  // RSFL as soon as one status is waiting
  reg(kIntSts) = 0xffffffffu;
  reg(kIntEn) = kIntRsfl;
  reg(kIrqCfg) = kIrqEn | kIrqPol | kIrqType;
  nvic_icpr0() = 1u << kIrq;
  nvic_iser0() = 1u << kIrq;
  return true;
}

bool Lan9118::rx_pending() const { return ((reg(kRxFifoInf) >> 16) & 0xffu) != 0; }

int Lan9118::receive(std::uint8_t* frame, std::size_t capacity) {
  if (!rx_pending()) return -1;
  const std::uint32_t status = reg(kRxStatus);
  const std::size_t length = (status >> 16) & 0x3fffu;  // with the 4-byte FCS
  const std::size_t words = (length + 3) / 4;
  if ((status & kRxStatusError) != 0 || length < 4 + 14 || length - 4 > capacity || length - 4 > kMaxFrame) {
    for (std::size_t i = 0; i < words; ++i) discard(reg(kRxData));  // drain it
    ++frames_dropped_;
    return 0;
  }
  const std::size_t size = length - 4;
  std::size_t at = 0;
  for (std::size_t i = 0; i < words; ++i) {
    const std::uint32_t w = reg(kRxData);
    for (int b = 0; b < 4; ++b, ++at) {
      if (at < size) frame[at] = static_cast<std::uint8_t>(w >> (8 * b));
    }
  }
  return static_cast<int>(size);
}

bool Lan9118::send(const std::uint8_t* frame, std::size_t size) {
  while (((reg(kTxFifoInf) >> 16) & 0xffu) != 0) discard(reg(kTxStatus));  // statuses not needed: drop them
  const std::size_t words = (size + 3) / 4;
  if (size < 14 || size > 1514 || (reg(kTxFifoInf) & 0xffffu) < 4 * words + 8) {
    ++tx_full_;
    return false;
  }
  ++tx_tag_;
  reg(kTxData) = kTxFirst | kTxLast | static_cast<std::uint32_t>(size);
  reg(kTxData) = std::uint32_t{tx_tag_} << 16 | static_cast<std::uint32_t>(size);
  for (std::size_t i = 0; i < words; ++i) {
    std::uint32_t w = 0;
    for (std::size_t b = 0; b < 4; ++b) {
      const std::size_t at = 4 * i + b;
      if (at < size) w |= std::uint32_t{frame[at]} << (8 * b);
    }
    reg(kTxData) = w;
  }
  return true;
}

void Lan9118::clear_rx_interrupt() {
  reg(kIntSts) = kIntRsfl;
  nvic_icpr0() = 1u << kIrq;
}

}  // namespace rockwatch::m4
