#!/usr/bin/env python3
"""Writes the binary seed corpora of the modbus_registers and can_frames fuzz targets from the
example configurations' register map and CAN frames (config/examples/volcompd-modbus-tcp.json,
volcompd-can.json with vmc-can.dbc): replies and frames a controller in the state of the example
would send. Run from the repository root; the files are committed (fuzz/corpus/)."""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def words(values):
    return b"".join(struct.pack("<H", w & 0xFFFF) for w in values)


def int32_abcd(counts):
    c = counts & 0xFFFFFFFF
    return [c >> 16, c & 0xFFFF]


# modbus_registers: mode 0 = one value (format byte: type + 6 * order, bit 7 sign; scale index).
types = {"int16": 0, "uint16": 1, "int32": 2, "uint32": 3, "float32": 4, "float64": 5}
orders = {"ABCD": 0, "CDAB": 1, "BADC": 2, "DCBA": 3}
f32 = struct.unpack(">HH", struct.pack(">f", 123.4567))
f64 = struct.unpack(">HHHH", struct.pack(">d", -250.125))
write("modbus_registers", "value-int32-abcd", bytes([0, types["int32"], 2]) + words(int32_abcd(1234567) + [0, 0]))
write("modbus_registers", "value-float32-cdab", bytes([0, types["float32"] + 6 * orders["CDAB"], 0]) + words([f32[1], f32[0], 0, 0]))
write("modbus_registers", "value-float64-dcba", bytes([0, types["float64"] + 6 * orders["DCBA"] | 0x80, 1]) + words([((w & 0xFF) << 8) | (w >> 8) for w in reversed(f64)]))
write("modbus_registers", "value-int16-neg", bytes([0, types["int16"], 2]) + words([(-1500) & 0xFFFF, 0, 0, 0]))
# mode 1: the example TCP map (holding 0..13 read: positions, enable/homed, sequence, applied).
reply = int32_abcd(1234567) + int32_abcd(2500000) + int32_abcd(-3000000) + [0b11, 42] + \
    int32_abcd(12) + int32_abcd(-7) + int32_abcd(0)
write("modbus_registers", "map-tcp-reply", bytes([1, 0]) + words(reply))
write("modbus_registers", "map-rtu-reply", bytes([1, 1]) + words(reply))
# mode 2: a map built from the input, laid out as the example (holding, int32 ABCD, 10000/mm).
def value(address, table=0, fmt=types["int32"], scale=2):
    return bytes([table]) + struct.pack("<H", address) + bytes([fmt, scale])
built = bytes([2, 2 | 8])  # sequence and applied offsets mapped
built += value(0) + value(2) + value(4)
built += bytes([0]) + struct.pack("<H", 6) + bytes([1]) + struct.pack("<H", 6)  # enable, homed
built += struct.pack("<H", 7)  # sequence
built += value(8) + value(10) + value(12)  # applied
built += value(14) + value(16) + value(18)  # offsets
built += struct.pack("<HH", 20, 21)  # status, heartbeat
write("modbus_registers", "map-built-reply", built + words(reply))

# can_frames: byte 0 bit 0 = FD layout; then datagrams: size index (0 = CAN_MTU, 1 = CANFD_MTU),
# can_id (LE), len, flags, payload (8 or 64 bytes).
def datagram(can_id, payload, fd=False, size=None):
    size = (1 if fd else 0) if size is None else size
    room = 64 if size == 1 else 8
    body = (payload + bytes(room))[:room]
    return bytes([size]) + struct.pack("<I", can_id) + bytes([len(payload), 0]) + body


def signal(bits, start, length, value):
    return bits | ((value & ((1 << length) - 1)) << start)


def positions(x, y, seq):
    v = signal(0, 0, 28, x) | signal(0, 28, 28, y) | signal(0, 56, 8, seq)
    return v.to_bytes(8, "little")


def axis_z(z, enable, homed, seq):
    v = signal(0, 0, 32, z) | (enable << 32) | (homed << 33) | signal(0, 56, 8, seq)
    return v.to_bytes(8, "little")


def applied(x, y, z, seq):
    v = signal(0, 0, 16, x) | signal(0, 16, 16, y) | signal(0, 32, 16, z) | signal(0, 56, 8, seq)
    return v.to_bytes(8, "little")


def cycle(seq, fd=False):
    return (datagram(256, positions(1234567, -2500000, seq), fd) +
            datagram(257, axis_z(-3000000, 1, 1, seq), fd) +
            datagram(258, applied(12, -7, 0, seq), fd))


write("can_frames", "two-cycles", bytes([0]) + cycle(1) + cycle(2))
write("can_frames", "fd-cycle", bytes([1]) + cycle(7, fd=True))
CAN_ERR_FLAG, CAN_RTR_FLAG, CAN_EFF_FLAG = 0x20000000, 0x40000000, 0x80000000
errors = datagram(CAN_ERR_FLAG | 0x04, bytes([0, 0x20, 0, 0, 0, 0, 0, 0]))  # controller: passive
errors += datagram(CAN_ERR_FLAG | 0x40, bytes(8))  # bus off
errors += datagram(CAN_ERR_FLAG | 0x100, bytes(8))  # restarted
errors += datagram(CAN_RTR_FLAG | 256, b"")  # remote request
errors += datagram(256, positions(1, 2, 3) + bytes(4), size=0)  # 12 bytes in a classical frame
errors += datagram(CAN_EFF_FLAG | 256, positions(1, 2, 3))  # right id, other format
errors += datagram(257, bytes(4))  # too short
write("can_frames", "hostile-mix", bytes([0]) + errors + cycle(9))


# modbus_server_requests: PDUs a master sends to the example server bank (positions 0-5, flags 6,
# life counter 7, applied offsets 8-13; outputs 14-21), each a length byte and the PDU.
def pdu(*parts):
    body = b"".join(parts)
    return bytes([len(body)]) + body


def be(*values):
    return b"".join(struct.pack(">H", v & 0xFFFF) for v in values)


cycle_tcp = (pdu(bytes([16]), be(0, 14), bytes([28]), be(*range(14))) +  # write the input block
             pdu(bytes([3]), be(14, 8)))  # read the outputs
write("modbus_server_requests", "fc16-fc03-cycle", cycle_tcp + cycle_tcp)
write("modbus_server_requests", "fc23-cycle",
      pdu(bytes([23]), be(14, 8, 0, 14), bytes([28]), be(*range(14))))
write("modbus_server_requests", "piecewise-and-refused",
      pdu(bytes([6]), be(0, 1)) + pdu(bytes([6]), be(1, 2)) +
      pdu(bytes([16]), be(2, 4), bytes([8]), be(1, 2, 3, 4)) +
      pdu(bytes([22]), be(6, 0xFFFC, 3)) +
      pdu(bytes([16]), be(12, 4), bytes([8]), be(0, 0, 0, 0)) +  # into the outputs: refused
      pdu(bytes([3]), be(20, 4)) + pdu(bytes([4]), be(0, 1)) +  # past the bank; input registers
      pdu(bytes([3])) + pdu(b""))
