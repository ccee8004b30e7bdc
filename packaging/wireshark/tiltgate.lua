-- tiltgate.lua: Wireshark dissectors for the serial protocols tiltgate captures.
--
--   tiltgate_rieker      Rieker Flex H6 / H4360 RS485 frames, CRC-16/ARC
--   tiltgate_dyna_ascii  Spectron SPECTROTILT Dyna "Modbus protocol" (':' hex LRC CR LF)
--   tiltgate_dyna9       Spectron SPECTROTILT Dyna 9-bit addressing ASCII protocol
--
-- A capture (pcapng, link type 252 "upper PDU export") names one of these in each packet, so
-- Wireshark picks them with no preference set. Install for one user:
--   cp tiltgate.lua ~/.local/lib/wireshark/plugins/
-- or load it for one run, from the Debian package:
--   wireshark -X lua_script:/usr/share/tiltgate/tiltgate.lua capture.pcapng
--
-- The frame layouts, the checksums and the vendor documents' errata are in docs/protocols.md;
-- the sections cited below are its headings. The packet's direction comes from its flags
-- (pinfo.p2p_dir: 0 sent = request, 1 received = reply); without them it is guessed.
-- Wireshark 4.0 runs Lua 5.2: bit operations are bit32's.

local band, bxor, rshift = bit32.band, bit32.bxor, bit32.rshift

---------------------------------------------------------------------------------------------
-- Shared by the three protocols
---------------------------------------------------------------------------------------------

local CHECK_BAD, CHECK_GOOD = 0, 1
-- The frame's time as an NSTime: pinfo.abs_ts is a double, too coarse for a time between frames.
local frame_time_field = Field.new("frame.time_epoch")
local function frame_time()
  local field = frame_time_field()
  return field and field.value
end
local check_status = { [CHECK_BAD] = "Bad", [CHECK_GOOD] = "Good" }
local directions = { [0] = "Request", [1] = "Reply" }

-- The shortest text that reads back as the same float32, so an angle shows as "-0.793396",
-- not as the double it is held in.
local function float_text(v)
  if v ~= v then return "NaN" end
  if v == math.huge or v == -math.huge then return v > 0 and "inf" or "-inf" end
  local packed = Struct.pack(">f", v)
  for digits = 6, 8 do
    local text = string.format("%." .. digits .. "g", v)
    if Struct.pack(">f", tonumber(text)) == packed then return text end
  end
  return string.format("%.9g", v)
end

local function name_or_unknown(names, code)
  return names[code] or string.format("Unknown (0x%02X)", code)
end

-- Fields and expert infos every protocol has, under its own abbreviation.
-- `check`: the frame's checksum, { name = "CRC", bits = 16 }, or nil.
local function common_fields(abbr, check)
  local f = {
    direction = ProtoField.uint8(abbr .. ".direction", "Direction", base.DEC, directions),
    request_in = ProtoField.framenum(abbr .. ".request_in", "Request in frame", base.NONE,
                                     frametype.REQUEST),
    response_in = ProtoField.framenum(abbr .. ".response_in", "Response in frame", base.NONE,
                                      frametype.RESPONSE),
    time = ProtoField.relative_time(abbr .. ".time", "Time since request"),
  }
  if check then
    local name, prefix = check.name, abbr .. "." .. check.name:lower()
    local uint = check.bits == 16 and ProtoField.uint16 or ProtoField.uint8
    f.check = uint(prefix, name, base.HEX)
    f.check_computed = uint(prefix .. ".computed", "Computed " .. name, base.HEX)
    f.check_status = ProtoField.uint8(prefix .. ".status", name .. " status", base.DEC,
                                      check_status)
  end
  local e = {
    malformed = ProtoExpert.new(abbr .. ".malformed", "Malformed frame", expert.group.MALFORMED,
                                expert.severity.ERROR),
    unknown = ProtoExpert.new(abbr .. ".unknown", "Unknown function", expert.group.UNDECODED,
                              expert.severity.WARN),
    unexpected = ProtoExpert.new(abbr .. ".unexpected", "Data not as documented",
                                 expert.group.PROTOCOL, expert.severity.WARN),
    guessed = ProtoExpert.new(abbr .. ".direction_guessed", "Direction guessed",
                              expert.group.ASSUMPTION, expert.severity.NOTE),
  }
  if check then
    e.bad_check = ProtoExpert.new(abbr .. "." .. check.name:lower() .. ".bad", "Bad " .. check.name,
                                  expert.group.CHECKSUM, expert.severity.ERROR)
  end
  return f, e
end

local function register(proto, f, e)
  local fields, experts = {}, {}
  for _, field in pairs(f) do fields[#fields + 1] = field end
  for _, info in pairs(e) do experts[#experts + 1] = info end
  proto.fields = fields
  proto.experts = experts
end

-- Pairs replies with requests on the first pass (frames in capture order), and remembers the
-- pairs for later passes (the GUI dissects a frame again whenever it is shown).
local function new_tracker()
  local t = {}
  function t.reset()
    t.last = nil         -- the last request seen: { frame, time, ... what the protocol keeps }
    t.request_of = {}    -- reply frame -> its request
    t.response_of = {}   -- request frame -> its first reply frame
  end
  t.reset()
  -- The request this frame answers, if `matches(request)` says so.
  function t.request_for(pinfo, matches)
    if pinfo.visited then return t.request_of[pinfo.number] end
    local request = t.last
    if request and matches(request) then
      t.request_of[pinfo.number] = request
      t.response_of[request.frame] = t.response_of[request.frame] or pinfo.number
      return request
    end
  end
  function t.note_request(pinfo, request)
    request.frame, request.time = pinfo.number, frame_time()
    if not pinfo.visited then t.last = request end
  end
  return t
end

-- Whether the frame is a reply, from the packet's flags, or `guess()` when they say nothing.
local function is_reply(pinfo, tree, f, e, guess)
  local dir = pinfo.p2p_dir
  local guessed = dir ~= 0 and dir ~= 1
  local reply = (dir == 1) or (guessed and guess())
  local item = tree:add(f.direction, reply and 1 or 0):set_generated()
  if guessed then
    item:append_text(" (guessed)")
    tree:add_proto_expert_info(e.guessed, "The capture gives no direction: guessed from the frame")
  end
  return reply
end

local function add_exchange(tree, f, tracker, pinfo, reply, request)
  if reply and request then
    tree:add(f.request_in, request.frame):set_generated()
    local now = frame_time()
    if now and request.time then tree:add(f.time, now - request.time):set_generated() end
  elseif not reply then
    local response = tracker.response_of[pinfo.number]
    if response then tree:add(f.response_in, response):set_generated() end
  end
end

-- `digits`: the checksum's width in hex digits, for the message (0x00CC, not 0xCC).
local function add_check(tree, f, e, range, received, computed, name, digits)
  tree:add(f.check, range, received)
  tree:add(f.check_computed, range, computed):set_generated()
  local good = received == computed
  tree:add(f.check_status, range, good and CHECK_GOOD or CHECK_BAD):set_generated()
  if not good then
    local hex = "0x%0" .. digits .. "X"
    tree:add_tvb_expert_info(e.bad_check, range, string.format(
      "Bad %s: " .. hex .. " received, " .. hex .. " computed", name, received, computed))
  end
  return good
end

-- Runs a dissector so that a mistake in it marks the frame malformed instead of raising a Lua
-- error in the packet tree.
local function guarded(body, proto, e)
  return function(tvb, pinfo, tree)
    local subtree = tree:add(proto, tvb())
    local ok, err = pcall(body, tvb, pinfo, subtree)
    if not ok then
      subtree:add_proto_expert_info(e.malformed, "Could not decode: " .. tostring(err))
      pinfo.cols.info = "Malformed: could not decode"
    end
    return tvb:len()
  end
end

local function info(pinfo, reply, parts)
  pinfo.cols.info = (reply and "Reply: " or "Request: ") .. table.concat(parts, ", ")
end

---------------------------------------------------------------------------------------------
-- Rieker Flex (docs/protocols.md, "Rieker frame layout", "Rieker functions and data")
-- [DEST u16][SRC u16][FUNCT u16][DL u8][DATA][CRC u16], big-endian, the CRC included.
---------------------------------------------------------------------------------------------

local rieker = Proto("tiltgate_rieker", "Rieker Flex RS485")

-- Table 2, "RS485 Function List", as named in docs/protocols.md.
local rieker_functions = {
  [0] = "ACK", [1] = "NAK", [2] = "Set Address", [3] = "Get Address", [4] = "Check Address",
  [5] = "Get Angle", [10] = "Change Lock", [16] = "Restart", [25] = "Set Zero To Value",
  [26] = "Set Zero To Angle", [28] = "Get Firmware Revision", [30] = "Get Lock Level",
  [37] = "Get Serial Number", [38] = "Set Baud", [41] = "Set Filter Response",
}
local nak_codes = {  -- "NAK" error codes
  [0] = "CRC failure", [1] = "Unknown function",
  [2] = "Function not valid for this sensor or mode of operation",
  [3] = "Data invalid for given function", [4] = "Invalid lock level to execute command",
  [5] = "Sensor busy, wait and try again",
}
local angle_types = { [1] = "Single axis", [2] = "X axis", [3] = "Y axis", [4] = "X and Y axes" }
local axis_codes = { [1] = "X axis (or single axis)", [2] = "Y axis" }
local zero_types = { [0] = "Temporary", [1] = "Permanent" }
local lock_levels = { [0] = "Locked", [1] = "Unlocked" }
local baud_codes = {  -- "Set Baud"; the factory default is code 4 (docs/protocols.md errata)
  [1] = "9600", [2] = "38400", [3] = "115200", [4] = "125000", [5] = "128000", [6] = "250000",
  [7] = "19200", [8] = "62500",
}
local BROADCAST = 0xFFFC
local LOCK_PASSWORD = 12345678

local rf, re = common_fields("tiltgate_rieker", { name = "CRC", bits = 16 })
rf.dest = ProtoField.uint16("tiltgate_rieker.dest", "Destination", base.DEC_HEX)
rf.src = ProtoField.uint16("tiltgate_rieker.src", "Source", base.DEC_HEX)
rf.funct = ProtoField.uint16("tiltgate_rieker.funct", "Function", base.DEC, rieker_functions)
rf.dl = ProtoField.uint8("tiltgate_rieker.dl", "Data length", base.DEC)
rf.data = ProtoField.bytes("tiltgate_rieker.data", "Data")
rf.extra = ProtoField.bytes("tiltgate_rieker.extra", "Bytes after the frame")
rf.new_address = ProtoField.uint16("tiltgate_rieker.new_address", "New address", base.DEC_HEX)
rf.address = ProtoField.uint16("tiltgate_rieker.address", "Sensor address", base.DEC_HEX)
rf.angle_type = ProtoField.uint8("tiltgate_rieker.angle_type", "Angle type", base.DEC, angle_types)
rf.angle = ProtoField.float("tiltgate_rieker.angle", "Angle")
rf.angle_x = ProtoField.float("tiltgate_rieker.angle_x", "X angle")
rf.angle_y = ProtoField.float("tiltgate_rieker.angle_y", "Y angle")
rf.lock_level = ProtoField.uint8("tiltgate_rieker.lock_level", "Lock level", base.DEC, lock_levels)
rf.password = ProtoField.uint32("tiltgate_rieker.password", "Password", base.DEC)
rf.axis = ProtoField.uint8("tiltgate_rieker.axis", "Axis", base.DEC, axis_codes)
rf.offset = ProtoField.float("tiltgate_rieker.offset", "Zero offset")
rf.zero_type = ProtoField.uint8("tiltgate_rieker.zero_type", "Zero type", base.DEC, zero_types)
rf.firmware = ProtoField.string("tiltgate_rieker.firmware", "Firmware revision")
rf.serial = ProtoField.string("tiltgate_rieker.serial", "Serial number")
rf.baud_code = ProtoField.uint8("tiltgate_rieker.baud_code", "Baud code", base.DEC, baud_codes)
rf.filter = ProtoField.uint8("tiltgate_rieker.filter", "Filter response", base.DEC)
rf.nak_code = ProtoField.uint8("tiltgate_rieker.nak_code", "NAK code", base.DEC, nak_codes)
register(rieker, rf, re)

local rieker_tracker = new_tracker()
function rieker.init() rieker_tracker.reset() end

-- CRC-16/ARC: polynomial 0x8005 processed reflected (0xA001), initial value 0, no final xor
-- ("Rieker CRC16").
local crc_table = {}
for i = 0, 255 do
  local crc = i
  for _ = 1, 8 do
    crc = band(crc, 1) ~= 0 and bxor(rshift(crc, 1), 0xA001) or rshift(crc, 1)
  end
  crc_table[i] = crc
end
local function crc16(bytes)
  local crc = 0
  for i = 1, #bytes do
    crc = bxor(rshift(crc, 8), crc_table[band(bxor(crc, bytes:byte(i)), 0xFF)])
  end
  return crc
end

local function add_angle(tree, field, range, name)
  local v = range:float()
  tree:add(field, range):set_text(string.format("%s: %s degrees", name, float_text(v)))
  return float_text(v)
end

local function level_text(level)
  return string.format("level %d (%s)", level, lock_levels[level] or "undocumented")
end

local function text_of(range)
  return range:string():gsub(" +$", "")
end

-- Request data by function: each returns the Info text, or nil. `d` is the DATA range.
-- The expected DL is the entry's `dl` (a frame with another DL is flagged, not decoded).
local rieker_requests = {
  [2] = { dl = 2, decode = function(t, d)
    t:add(rf.new_address, d(0, 2))
    return "new address " .. d(0, 2):uint()
  end },
  [3] = { dl = 0 }, [4] = { dl = 0 }, [16] = { dl = 0 }, [28] = { dl = 0 }, [30] = { dl = 0 },
  [37] = { dl = 0 },
  [5] = { dl = 1, decode = function(t, d)
    t:add(rf.angle_type, d(0, 1))
    return name_or_unknown(angle_types, d(0, 1):uint())
  end },
  [10] = { dl = 5, decode = function(t, d)
    t:add(rf.lock_level, d(0, 1))
    local password = t:add(rf.password, d(1, 4))
    if d(1, 4):uint() == LOCK_PASSWORD then password:append_text(" (the documented password)") end
    return level_text(d(0, 1):uint())
  end },
  [25] = { dl = 5, decode = function(t, d)
    t:add(rf.axis, d(0, 1))
    local offset = add_angle(t, rf.offset, d(1, 4), "Zero offset")
    return name_or_unknown(axis_codes, d(0, 1):uint()) .. ", offset " .. offset
  end },
  [26] = { dl = 1, decode = function(t, d)
    t:add(rf.zero_type, d(0, 1))
    return name_or_unknown(zero_types, d(0, 1):uint()):lower()
  end },
  [38] = { dl = 1, decode = function(t, d)
    t:add(rf.baud_code, d(0, 1))
    local code = d(0, 1):uint()
    return string.format("code %d (%s baud)", code, baud_codes[code] or "undocumented")
  end },
  [41] = { dl = 1, decode = function(t, d)
    local level = d(0, 1):uint()
    local item = t:add(rf.filter, d(0, 1))
    if level < 1 or level > 6 then
      item:add_proto_expert_info(re.unexpected, "Filter response is 1..6")
    end
    return "level " .. level
  end },
}

local function decode_angles(t, d, dl, request)
  if dl == 8 then
    return "X=" .. add_angle(t, rf.angle_x, d(0, 4), "X angle") ..
           " Y=" .. add_angle(t, rf.angle_y, d(4, 4), "Y angle")
  end
  -- 4 bytes: which axis only the request says (type 1 single, 2 X, 3 Y).
  local type = request and request.angle_type
  if type == 2 then return "X=" .. add_angle(t, rf.angle_x, d(0, 4), "X angle") end
  if type == 3 then return "Y=" .. add_angle(t, rf.angle_y, d(0, 4), "Y angle") end
  return "angle=" .. add_angle(t, rf.angle, d(0, 4), "Angle")
end

-- Reply data by function, as rieker_requests; `dl` may be a set of lengths.
local rieker_replies = {
  [0] = { dl = 0 },
  [1] = { dl = 1, decode = function(t, d)
    t:add(rf.nak_code, d(0, 1))
    local code = d(0, 1):uint()
    return string.format("code %d: %s", code, nak_codes[code] or "undocumented")
  end },
  [3] = { dl = 2, decode = function(t, d)
    t:add(rf.address, d(0, 2))
    return "address " .. d(0, 2):uint()
  end },
  [5] = { dl = { [4] = true, [8] = true }, decode = decode_angles },
  [28] = { dl = 7, decode = function(t, d)
    t:add(rf.firmware, d(0, 7))
    return string.format('"%s"', text_of(d(0, 7)))
  end },
  [30] = { dl = 1, decode = function(t, d)
    t:add(rf.lock_level, d(0, 1))
    return level_text(d(0, 1):uint())
  end },
  [37] = { dl = 10, decode = function(t, d)
    t:add(rf.serial, d(0, 10))
    return string.format('serial "%s"', text_of(d(0, 10)))
  end },
}

local function dl_fits(spec, dl)
  if type(spec.dl) == "table" then return spec.dl[dl] == true end
  return spec.dl == dl
end

-- Without flags: ACK and NAK come from a sensor, and so does a reading function with data
-- the request does not carry. The rest are requests.
local function rieker_guess(funct, dl)
  if funct == 0 or funct == 1 then return true end
  local spec = rieker_replies[funct]
  return spec ~= nil and dl_fits(spec, dl) and not dl_fits(rieker_requests[funct], dl)
end

local function dissect_rieker(tvb, pinfo, tree)
  pinfo.cols.protocol = "Rieker"
  local len = tvb:len()
  if len < 9 then  -- DEST SRC FUNCT DL CRC: 9 bytes at least
    tree:add_proto_expert_info(re.malformed, string.format(
      "Too short: %d bytes, a frame has at least 9", len))
    pinfo.cols.info = string.format("Malformed: %d bytes, too short for a frame", len)
    return
  end
  local dest, src = tvb(0, 2):uint(), tvb(2, 2):uint()
  local funct, dl = tvb(4, 2):uint(), tvb(6, 1):uint()
  local reply = is_reply(pinfo, tree, rf, re, function() return rieker_guess(funct, dl) end)
  local request
  if reply then
    request = rieker_tracker.request_for(pinfo, function(r)
      -- An ACK answers only the functions that return no data (Table 2's "Expected Response").
      local answers = funct == r.funct or funct == 1 or (funct == 0 and not rieker_replies[r.funct])
      return dest == r.src and (src == r.dest or r.dest == BROADCAST) and answers
    end)
  else
    rieker_tracker.note_request(pinfo, { dest = dest, src = src, funct = funct,
      angle_type = (funct == 5 and dl == 1 and len >= 8) and tvb(7, 1):uint() or nil })
  end
  add_exchange(tree, rf, rieker_tracker, pinfo, reply, request)

  local dest_item = tree:add(rf.dest, tvb(0, 2))
  if dest == BROADCAST then dest_item:append_text(" (broadcast)") end
  tree:add(rf.src, tvb(2, 2))
  local funct_item = tree:add(rf.funct, tvb(4, 2))
  tree:add(rf.dl, tvb(6, 1))
  local sensor = reply and src or dest
  local parts = { "addr " .. sensor .. (sensor == BROADCAST and " (broadcast)" or ""),
                  name_or_unknown(rieker_functions, funct) }
  if not rieker_functions[funct] then
    funct_item:add_proto_expert_info(re.unknown, string.format(
      "Function %d is not a user function (reserved for the factory)", funct))
  end

  local whole = 9 + dl  -- "DL decides the length"
  if len < whole then
    if dl > 0 then tree:add(rf.data, tvb(7, len - 7)) end
    tree:add_proto_expert_info(re.malformed, string.format(
      "Truncated: DL %d makes a %d-byte frame, %d bytes here", dl, whole, len))
    parts[#parts + 1] = "truncated"
    info(pinfo, reply, parts)
    return
  end

  local data = dl > 0 and tvb(7, dl) or nil
  if data then tree:add(rf.data, data) end
  local spec = (reply and rieker_replies or rieker_requests)[funct]
  if reply and request and (funct == 0 or funct == 1) then  -- "ACK to Set Address"
    parts[#parts] = parts[#parts] .. " to " .. name_or_unknown(rieker_functions, request.funct)
  end
  if spec and dl_fits(spec, dl) then
    if spec.decode then parts[#parts + 1] = spec.decode(tree, data, dl, request) end
  elseif spec then
    tree:add_proto_expert_info(re.unexpected, string.format(
      "DL %d is not what %s carries in a %s", dl, name_or_unknown(rieker_functions, funct),
      reply and "reply" or "request"))
  elseif reply and rieker_functions[funct] then
    tree:add_proto_expert_info(re.unexpected, "The sensor answers this function with an ACK")
  end

  local good = add_check(tree, rf, re, tvb(7 + dl, 2), tvb(7 + dl, 2):uint(),
                         crc16(tvb:raw(0, 7 + dl)), "CRC", 4)
  if not good then parts[#parts + 1] = "bad CRC" end
  if len > whole then
    tree:add(rf.extra, tvb(whole))
    tree:add_proto_expert_info(re.malformed, string.format(
      "%d bytes after the frame: the byte count is not 9 + DL", len - whole))
    parts[#parts + 1] = "length does not match DL"
  end
  info(pinfo, reply, parts)
end

rieker.dissector = guarded(dissect_rieker, rieker, re)

---------------------------------------------------------------------------------------------
-- Spectron SPECTROTILT Dyna, both protocols (docs/protocols.md, "Dyna EEPROM map")
---------------------------------------------------------------------------------------------

local eeprom_locations = {
  [2] = "reserved", [4] = "serial number", [6] = "sensor offset", [8] = "reserved",
  [10] = "temperature sensor offset", [12] = "reserved", [14] = "reserved",
  [16] = "module address", [18] = "reserved", [20] = "PWM output offset", [22] = "baud rate code",
}
local dyna_baud_codes = {  -- location 22
  [7] = "38400", [10] = "28800", [15] = "19200", [32] = "9600", [64] = "4800",
}

local function location_meaning(location)
  local name = eeprom_locations[location]
  if not name and location >= 100 and location <= 280 and location % 2 == 0 then
    name = "reserved"
  end
  return name and " (" .. name .. ")" or ""
end

local function value_meaning(location, value)
  local baud = location == 22 and dyna_baud_codes[value]
  return baud and " (" .. baud .. " baud)" or ""
end

local function location_text(location)
  return "location " .. location .. location_meaning(location)
end

-- "location 22 (baud rate code) = 15 (19200 baud)"
local function eeprom_text(location, value)
  return location_text(location) .. " = " .. value .. value_meaning(location, value)
end

-- An EEPROM location, and its value when `value_range` is given, with their meanings.
local function add_eeprom(tree, f, location_range, location, value_range, value)
  tree:add(f.location, location_range, location):append_text(location_meaning(location))
  if value_range then
    tree:add(f.value, value_range, value):append_text(value_meaning(location, value))
  end
end

local function signed16(word)
  return word >= 0x8000 and word - 0x10000 or word
end

local function printable(text)
  return (text:gsub("[^\32-\126]", function(c) return string.format("\\x%02X", c:byte()) end))
end

---------------------------------------------------------------------------------------------
-- Dyna "Modbus protocol" (docs/protocols.md, "Dyna protocol 2 frame", "Dyna LRC")
-- ':' + address (2 hex) + command (2 hex) + data (hex) + LRC (2 hex) + CR LF.
---------------------------------------------------------------------------------------------

local dyna_ascii = Proto("tiltgate_dyna_ascii", "Spectron Dyna Modbus-ASCII protocol")

local ascii_commands = {
  [0x65] = "Reset", [0x66] = "Read Sensor", [0x67] = "Read Temperature",
  [0x68] = "Write EEPROM", [0x69] = "Read EEPROM", [0x6A] = "Send Revision",
}

local af, ae = common_fields("tiltgate_dyna_ascii", { name = "LRC", bits = 8 })
af.address = ProtoField.uint8("tiltgate_dyna_ascii.address", "Address", base.DEC)
af.command = ProtoField.uint8("tiltgate_dyna_ascii.command", "Command", base.HEX, ascii_commands)
af.data = ProtoField.string("tiltgate_dyna_ascii.data", "Data (hex digits)")
af.location = ProtoField.uint16("tiltgate_dyna_ascii.location", "EEPROM location", base.DEC)
af.value = ProtoField.uint16("tiltgate_dyna_ascii.value", "EEPROM value", base.DEC)
af.counts = ProtoField.int16("tiltgate_dyna_ascii.counts", "Sensor counts", base.DEC)
af.temperature = ProtoField.int16("tiltgate_dyna_ascii.temperature", "Temperature (raw)", base.DEC)
af.revision = ProtoField.string("tiltgate_dyna_ascii.revision", "Revision")
register(dyna_ascii, af, ae)

local ascii_tracker = new_tracker()
function dyna_ascii.init() ascii_tracker.reset() end

-- Data bytes each command carries, request and reply (the note; replies A6 of
-- spectron/assumptions.h: one 16-bit word).
local ascii_data = {
  [0x65] = { 0, 0 }, [0x66] = { 0, 2 }, [0x67] = { 0, 2 }, [0x68] = { 4, 0 }, [0x69] = { 2, 2 },
  [0x6A] = { 0, 2 },
}

-- Without flags: the data length tells, except for reset and read EEPROM, whose request and
-- reply look alike: then a reply when it answers the last request.
local function ascii_guess(address, command, bytes)
  local sizes = ascii_data[command]
  if not sizes then return false end
  if sizes[1] ~= sizes[2] then return bytes == sizes[2] end
  local last = ascii_tracker.last
  return last ~= nil and last.address == address and last.command == command and
         not ascii_tracker.response_of[last.frame]
end

-- Data of a well-framed frame: the Info text. `at` is the data's offset, `bytes` its values.
local function ascii_decode(tree, tvb, at, command, bytes, reply, request)
  local function word(i) return bytes[i] * 256 + bytes[i + 1] end
  local function range(i, n) return tvb(at + 2 * (i - 1), 2 * n) end
  local sizes = ascii_data[command]
  if not sizes then return nil end
  if #bytes ~= sizes[reply and 2 or 1] then
    tree:add_proto_expert_info(ae.unexpected, string.format(
      "%d data bytes, %s %s carries %d", #bytes, ascii_commands[command],
      reply and "reply" or "request", sizes[reply and 2 or 1]))
    return nil
  end
  if not reply then
    if command == 0x68 then
      add_eeprom(tree, af, range(1, 2), word(1), range(3, 2), word(3))
      return eeprom_text(word(1), word(3))
    elseif command == 0x69 then
      add_eeprom(tree, af, range(1, 2), word(1))
      return location_text(word(1))
    end
    return nil
  end
  if command == 0x66 then
    tree:add(af.counts, range(1, 2), signed16(word(1)))
    return "counts=" .. signed16(word(1))
  elseif command == 0x67 then
    tree:add(af.temperature, range(1, 2), signed16(word(1)))
    return "temperature=" .. signed16(word(1))
  elseif command == 0x69 then
    local location = request and request.location
    tree:add(af.value, range(1, 2), word(1)):append_text(value_meaning(location, word(1)))
    if location then return eeprom_text(location, word(1)) end
    return "value=" .. word(1)
  elseif command == 0x6A then  -- A7: high and low byte as "HH.LL"
    local revision = string.format("%02X.%02X", bytes[1], bytes[2])
    tree:add(af.revision, range(1, 2), revision)
    return "revision " .. revision
  end
  return "acknowledged"
end

local function dissect_dyna_ascii(tvb, pinfo, tree)
  pinfo.cols.protocol = "Dyna ASCII"
  local text = tvb:raw()
  local function malformed(why)
    tree:add_proto_expert_info(ae.malformed, why)
    pinfo.cols.info = "Malformed: " .. why .. ": \"" .. printable(text) .. "\""
  end
  if #text == 0 then return malformed("empty") end
  if text:sub(1, 1) ~= ":" then return malformed("does not start with ':'") end
  local ends = text:sub(-2) == "\r\n"
  local digits = text:sub(2, ends and -3 or -1)
  local bad = digits:find("[^%x]")
  if not ends then return malformed("does not end with CR LF") end
  if bad then return malformed(string.format("'%s' at offset %d is not a hex digit",
                                             printable(digits:sub(bad, bad)), bad)) end
  if #digits % 2 ~= 0 then return malformed("an odd number of hex digits") end
  if #digits < 6 then return malformed("too short: no address, command and LRC") end

  local bytes = {}
  for i = 1, #digits, 2 do bytes[#bytes + 1] = tonumber(digits:sub(i, i + 1), 16) end
  local address, command, lrc = bytes[1], bytes[2], bytes[#bytes]
  local data = { table.unpack(bytes, 3, #bytes - 1) }
  local reply = is_reply(pinfo, tree, af, ae, function()
    return ascii_guess(address, command, #data)
  end)
  local request
  if reply then
    request = ascii_tracker.request_for(pinfo, function(r)
      return r.address == address and r.command == command
    end)
  else
    ascii_tracker.note_request(pinfo, { address = address, command = command,
      location = #data >= 2 and data[1] * 256 + data[2] or nil })
  end
  add_exchange(tree, af, ascii_tracker, pinfo, reply, request)

  tree:add(af.address, tvb(1, 2), address)
  local command_item = tree:add(af.command, tvb(3, 2), command)
  local parts = { "addr " .. address, name_or_unknown(ascii_commands, command) }
  if not ascii_commands[command] then
    command_item:add_proto_expert_info(ae.unknown, "The note lists commands 0x65..0x6A only")
  end
  if #data > 0 then tree:add(af.data, tvb(5, 2 * #data)) end
  parts[#parts + 1] = ascii_decode(tree, tvb, 5, command, data, reply, request)

  -- The note's LRC: over the ASCII characters themselves, so the letter case counts.
  local sum = 0
  for i = 1, #digits - 2 do sum = sum + digits:byte(i) end
  if not add_check(tree, af, ae, tvb(#digits - 1, 2), lrc, band(-sum, 0xFF), "LRC", 2) then
    parts[#parts + 1] = "bad LRC"
  end
  info(pinfo, reply, parts)
end

dyna_ascii.dissector = guarded(dissect_dyna_ascii, dyna_ascii, ae)

---------------------------------------------------------------------------------------------
-- Dyna 9-bit addressing (docs/protocols.md, "Dyna protocol 1 commands"; assumptions A1..A5 of
-- spectron/assumptions.h). A request is the address byte (sent with the 9th bit set, which a
-- capture cannot show), one ASCII command, its decimal arguments, CR LF. A reply is a line of
-- text ending CR LF, with no address and no command: the request before it says what it is.
---------------------------------------------------------------------------------------------

local dyna9 = Proto("tiltgate_dyna9", "Spectron Dyna 9-bit protocol")

local nine_bit_commands = {
  [0x30] = "Reset Processor", [0x33] = "Read EEPROM", [0x41] = "Read Sensor",
  [0x43] = "Read Temperature", [0x45] = "Write EEPROM", [0x46] = "Send Firmware Revision",
}

local nf, ne = common_fields("tiltgate_dyna9", nil)
nf.address = ProtoField.uint8("tiltgate_dyna9.address", "Address", base.DEC)
nf.command = ProtoField.uint8("tiltgate_dyna9.command", "Command", base.HEX, nine_bit_commands)
nf.arguments = ProtoField.string("tiltgate_dyna9.arguments", "Arguments")
nf.location = ProtoField.uint16("tiltgate_dyna9.location", "EEPROM location", base.DEC)
nf.delimiter = ProtoField.string("tiltgate_dyna9.delimiter", "Delimiter")
nf.value = ProtoField.int32("tiltgate_dyna9.value", "EEPROM value", base.DEC)
nf.line = ProtoField.string("tiltgate_dyna9.line", "Reply line")
nf.counts = ProtoField.int32("tiltgate_dyna9.counts", "Sensor counts", base.DEC)
nf.temperature = ProtoField.int32("tiltgate_dyna9.temperature", "Temperature (raw)", base.DEC)
nf.firmware = ProtoField.string("tiltgate_dyna9.firmware", "Firmware revision")
register(dyna9, nf, ne)

local nine_tracker = new_tracker()
function dyna9.init() nine_tracker.reset() end

-- A request body without its CR LF: the command's arguments, checked (A2, A3): nil and why
-- when they are not as documented. Numbers are decimal, 1..5 digits, at most 65535.
local function nine_bit_arguments(command, args)
  local function word(digits)
    local n = digits and #digits <= 5 and tonumber(digits)
    return n and n <= 65535 and n or nil
  end
  if command == 0x33 then
    local location = word(args:match("^(%d+)$"))
    if not location then return nil, "Read EEPROM takes a decimal location" end
    return { location = location }
  elseif command == 0x45 then
    local location, delimiter, value = args:match("^(%d+)([ ,:\t])(%d+)$")
    location, value = word(location), word(value)
    if not (location and value) then
      return nil, "Write EEPROM takes a location, a delimiter (space , : tab) and a value"
    end
    return { location = location, delimiter = delimiter, value = value }
  elseif nine_bit_commands[command] then
    if args ~= "" then return nil, "this command takes no arguments" end
    return {}
  end
  return {}
end

-- Without flags: a request when the bytes after the first read as a command with its
-- arguments; anything else is a reply line.
local function nine_bit_guess(text)
  if #text < 4 or text:sub(-2) ~= "\r\n" then return true end
  local command = text:byte(2)
  return not (nine_bit_commands[command] and nine_bit_arguments(command, text:sub(3, -3)))
end

-- `bad(why)` marks the frame malformed.
local function dissect_nine_bit_request(tvb, tree, text, parts, bad)
  local address, command = text:byte(1), text:byte(2)
  tree:add(nf.address, tvb(0, 1)):append_text(" (sent with the 9th bit set)")
  parts[#parts + 1] = "addr " .. address
  if not command then
    bad("No command after the address byte")
    return { address = address }
  end
  local command_item = tree:add(nf.command, tvb(1, 1))
  command_item:append_text(string.format(" ('%s')", printable(string.char(command))))
  parts[#parts + 1] = name_or_unknown(nine_bit_commands, command)
  if not nine_bit_commands[command] then
    command_item:add_proto_expert_info(ne.unknown, "The note lists commands 0 3 A C E F only")
  end
  local ends = text:sub(-2) == "\r\n"
  if not ends then bad("The request does not end with CR LF") end
  local args_text = text:sub(3, ends and -3 or -1)
  if #args_text > 0 then tree:add(nf.arguments, tvb(2, #args_text)) end
  local args, why = nine_bit_arguments(command, args_text)
  if not args then
    bad(why)
    return { address = address, command = command }
  end
  if args.location then
    local digits = #args_text:match("^%d+")
    local value_range = args.delimiter and tvb(3 + digits, #args_text - digits - 1)
    add_eeprom(tree, nf, tvb(2, digits), args.location, value_range, args.value)
    if args.delimiter then
      tree:add(nf.delimiter, tvb(2 + digits, 1))
      parts[#parts + 1] = eeprom_text(args.location, args.value)
    else
      parts[#parts + 1] = location_text(args.location)
    end
  end
  return { address = address, command = command, location = args.location }
end

-- A4: '3', 'A' and 'C' answer one decimal number, 'F' free text, '0' and 'E' any line.
local nine_bit_numbers = { [0x33] = { nf.value, "value" }, [0x41] = { nf.counts, "counts" },
                           [0x43] = { nf.temperature, "temperature" } }

local function dissect_nine_bit_reply(tvb, tree, text, request, parts, bad)
  local stop = text:find("\r\n", 1, true)
  local line = text:sub(1, (stop or #text + 1) - 1)
  if request then
    parts[#parts + 1] = "addr " .. request.address
    if request.command then  -- a request of an address byte alone has none
      parts[#parts + 1] = name_or_unknown(nine_bit_commands, request.command)
    end
  end
  if #line > 0 then tree:add(nf.line, tvb(0, #line)) end
  if not stop then
    bad("The reply does not end with CR LF")
  elseif stop + 1 < #text then
    bad(string.format("%d bytes after the line's CR LF", #text - stop - 1))
  end
  local command = request and request.command
  local number = nine_bit_numbers[command]
  if number then
    -- One decimal number that fits 32 bits, spaces around it tolerated (A4).
    local value = tonumber(line:match("^[ \t]*([+-]?%d+)[ \t]*$") or "")
    if value and value >= -2 ^ 31 and value < 2 ^ 31 then
      local location = command == 0x33 and request.location
      tree:add(number[1], tvb(0, #line), value):append_text(value_meaning(location, value))
      parts[#parts + 1] = location and eeprom_text(location, value) or number[2] .. "=" .. value
    else
      tree:add_proto_expert_info(ne.unexpected, "Not the one decimal number this command returns")
      parts[#parts + 1] = string.format('"%s"', printable(line))
    end
  elseif command == 0x46 then
    tree:add(nf.firmware, tvb(0, #line))
    parts[#parts + 1] = string.format('revision "%s"', printable(line))
  elseif command == 0x30 or command == 0x45 then
    parts[#parts + 1] = "acknowledged"
  else
    parts[#parts + 1] = string.format('line "%s"', printable(line))
  end
end

local function dissect_dyna9(tvb, pinfo, tree)
  pinfo.cols.protocol = "Dyna 9-bit"
  local text = tvb:raw()
  local reply = is_reply(pinfo, tree, nf, ne, function() return nine_bit_guess(text) end)
  local parts, request, malformed = {}, nil, false
  local function bad(why)
    tree:add_proto_expert_info(ne.malformed, why)
    malformed = true
  end
  if reply then
    request = nine_tracker.request_for(pinfo, function() return true end)
  end
  add_exchange(tree, nf, nine_tracker, pinfo, reply, request)
  if reply then
    dissect_nine_bit_reply(tvb, tree, text, request, parts, bad)
  elseif #text > 0 then
    nine_tracker.note_request(pinfo, dissect_nine_bit_request(tvb, tree, text, parts, bad))
  else
    bad("Empty request")
  end
  if malformed then parts[#parts + 1] = "malformed" end
  info(pinfo, reply, parts)
end

dyna9.dissector = guarded(dissect_dyna9, dyna9, ne)
