// A polled driver for the SMSC LAN9118 Ethernet controller of QEMU's mps2-an386 board (at 0x40200000, IRQ 13):
// soft reset, MAC address, MAC_CR with the receiver and transmitter on and every multicast frame passed (MCPAS: the
// IPv4 path below keeps only the monitor's group and port, so the hash filter would add nothing but its setup), one
// frame at a time out of the RX status and data FIFOs, one frame at a time into the TX data FIFO (command words A and
// B, the frame as little-endian words). No allocation: the caller owns the buffers.
//
// The interrupt line (RX status FIFO level, RSFL) is enabled so that the main loop can sleep in WFI with PRIMASK set:
// a pending interrupt wakes WFI without being taken, and the loop polls (docs: firmware/README.md, "The monitor on the
// wire").
#pragma once

#include <cstddef>
#include <cstdint>

namespace rockwatch::m4 {

class Lan9118 {
 public:
  static constexpr std::uintptr_t kBase = 0x40200000u;
  static constexpr int kIrq = 13;            // the board's NVIC line
  static constexpr std::size_t kMaxFrame = 1536;  // bytes of a frame the driver receives (larger ones are dropped)

  // Resets the controller and starts it with this MAC address; false when it does not answer as a LAN9118.
  bool init(const std::uint8_t mac[6]);
  // A received frame is waiting in the RX FIFOs.
  bool rx_pending() const;
  // Takes the next frame into `frame` (its bytes without the FCS): the length, 0 for a frame dropped (an error bit in
  // its status, or longer than kMaxFrame: counted), or -1 when none was waiting.
  int receive(std::uint8_t* frame, std::size_t capacity);
  // Sends one frame of `size` bytes (14 ≤ size ≤ 1514); false when the TX FIFO has no room (counted).
  bool send(const std::uint8_t* frame, std::size_t size);
  // Acknowledges the receive interrupt (after the RX FIFOs were drained) and the NVIC's pending bit.
  void clear_rx_interrupt();

  std::uint32_t frames_dropped() const { return frames_dropped_; }  // error status or too long
  std::uint32_t tx_full() const { return tx_full_; }

 private:
  static volatile std::uint32_t& reg(std::uint32_t offset) {
    return *reinterpret_cast<volatile std::uint32_t*>(kBase + offset);
  }
  void mac_write(std::uint32_t index, std::uint32_t value);
  std::uint32_t mac_read(std::uint32_t index);
  std::uint32_t frames_dropped_ = 0, tx_full_ = 0;
  std::uint16_t tx_tag_ = 0;
};

}  // namespace rockwatch::m4
