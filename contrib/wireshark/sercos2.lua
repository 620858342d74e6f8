-- sercos2.lua: Wireshark dissector for SERCOS II telegrams captured by the sercon ring
-- simulator (crate sercos-sim, module trace).
--
-- Link type: LINKTYPE_USER0 (147, Wireshark encapsulation wtap USER0). Each packet is a 24-byte
-- pseudo-header followed by the telegram bytes (ADR and message field, without the flags and
-- without the FCS; ERRATA.md, Telegrams: frame). All multi-byte fields are little endian, as
-- SERCOS words are on the line.
--
--   offset size field
--   0      1    version (1)
--   1      1    header length in bytes (24); the telegram starts here
--   2      2    segment number
--   4      1    flags: bit 0 origin (0 master, 1 slave), bit 1 FCS ok,
--                      bit 2 FCS fields valid, bit 3 line error
--   5      1    line error: 0 none, 1 FCS mismatch, 2 abort, 3 too short,
--                           4 not whole bytes, 5 too long
--   6      2    bit rate in Mbit/s (2, 4, 8, 16), 0 unknown
--   8      2    FCS as received
--   10     2    FCS computed over the telegram bytes
--   12     4    reserved (0)
--   16     8    time in picoseconds since the start of the simulation
--
-- The telegram fields follow sercos-telegrams.md (MST, MDT, AT, control and status words).
--
-- Use:  wireshark -X lua_script:contrib/wireshark/sercos2.lua trace.pcap
--       tshark -X lua_script:contrib/wireshark/sercos2.lua -r trace.pcap -V
-- or copy this file into the personal Lua plugins folder (Help > About > Folders).

local sercos2 = Proto("sercos2", "SERCOS II telegram (sercon simulator)")

local HEADER_LEN = 24

-- Pseudo-header -----------------------------------------------------------------------------

local origin_names = { [0] = "master", [1] = "slave" }
local line_error_names = {
    [0] = "none",
    [1] = "FCS mismatch",
    [2] = "abort (seven 1s)",
    [3] = "too short",
    [4] = "not whole bytes",
    [5] = "too long",
}

local f = {}
f.version     = ProtoField.uint8("sercos2.version", "Pseudo-header version", base.DEC)
f.header_len  = ProtoField.uint8("sercos2.header_len", "Pseudo-header length", base.DEC)
f.segment     = ProtoField.uint16("sercos2.segment", "Segment", base.DEC)
f.flags       = ProtoField.uint8("sercos2.flags", "Flags", base.HEX)
f.origin      = ProtoField.uint8("sercos2.origin", "Origin", base.DEC, origin_names, 0x01)
f.fcs_ok      = ProtoField.bool("sercos2.fcs_ok", "FCS ok", 8, nil, 0x02)
f.fcs_valid   = ProtoField.bool("sercos2.fcs_valid", "FCS fields valid", 8, nil, 0x04)
f.line_err_fl = ProtoField.bool("sercos2.line_error_flag", "Line error", 8, nil, 0x08)
f.line_error  = ProtoField.uint8("sercos2.line_error", "Line error kind", base.DEC, line_error_names)
f.bit_rate    = ProtoField.uint16("sercos2.bit_rate", "Bit rate (Mbit/s)", base.DEC)
f.fcs_rx      = ProtoField.uint16("sercos2.fcs_received", "FCS received", base.HEX)
f.fcs_calc    = ProtoField.uint16("sercos2.fcs_computed", "FCS computed", base.HEX)
f.reserved    = ProtoField.uint32("sercos2.reserved", "Reserved", base.HEX)
f.time_ps     = ProtoField.uint64("sercos2.time_ps", "Time (ps)", base.DEC)

-- Telegram -----------------------------------------------------------------------------------

-- sercos-telegrams.md, ADR: 0 = no station, 1-254 = drives, 255 = broadcast.
local adr_names = { [0] = "no station", [255] = "broadcast" }
for drive = 1, 254 do
    adr_names[drive] = "drive " .. drive
end
f.kind        = ProtoField.string("sercos2.kind", "Telegram")
f.adr         = ProtoField.uint8("sercos2.adr", "ADR", base.DEC, adr_names)
f.received    = ProtoField.bytes("sercos2.received", "Bytes received before the error")

-- MST: sercos-telegrams.md, Master Synchronization Telegram: "The lower 3 bits designate the
-- SERCOS phase (0 - 4)".
f.mst_byte    = ProtoField.uint8("sercos2.mst.phase_byte", "Phase byte", base.HEX)
f.mst_phase   = ProtoField.uint8("sercos2.mst.phase", "Communication phase", base.DEC, nil, 0x07)
f.mst_other   = ProtoField.uint8("sercos2.mst.other_bits", "Other bits", base.HEX, nil, 0xF8)

-- Data record: sercos-telegrams.md, Data Record: 16-bit control/status word, 16-bit service
-- info, data block.
f.record      = ProtoField.bytes("sercos2.record", "Data record")
f.record_off  = ProtoField.uint16("sercos2.record.offset", "Record offset", base.DEC)
f.service     = ProtoField.uint16("sercos2.service_info", "Service info", base.HEX)
f.data_block  = ProtoField.bytes("sercos2.data_block", "Data block")
f.malformed   = ProtoField.bytes("sercos2.malformed", "Malformed (too short for its kind)")

-- MDT control word: sercos-telegrams.md, Master Data Telegram, bits 15-0.
local op_mode_names = {
    [0] = "primary op mode (S-0-0032)",
    [1] = "secondary op mode 1 (S-0-0033)",
    [2] = "secondary op mode 2 (S-0-0034)",
    [3] = "secondary op mode 3 (S-0-0035)",
}
local element_names = {
    [0] = "service channel not active",
    [1] = "IDN (number) of the op data",
    [2] = "name of operation data",
    [3] = "attribute of op data",
    [4] = "units of op data",
    [5] = "min input value",
    [6] = "max input value",
    [7] = "operation data",
}
f.cw          = ProtoField.uint16("sercos2.mdt.cw", "Control word", base.HEX)
f.cw_on       = ProtoField.bool("sercos2.mdt.cw.drive_on", "Drive ON (bit 15)", 16,
                    { "drive ON", "drive OFF" }, 0x8000)
f.cw_enable   = ProtoField.bool("sercos2.mdt.cw.drive_enable", "Drive enable (bit 14)", 16,
                    { "drive enable", "drive disable" }, 0x4000)
f.cw_restart  = ProtoField.bool("sercos2.mdt.cw.drive_restart", "Drive halt/restart (bit 13)", 16,
                    { "drive restart", "drive halt" }, 0x2000)
f.cw_res      = ProtoField.uint16("sercos2.mdt.cw.reserved", "Reserved (bits 12-11)", base.HEX,
                    nil, 0x1800)
f.cw_sync     = ProtoField.bool("sercos2.mdt.cw.sync", "Control unit synchronization bit (bit 10)",
                    16, nil, 0x0400)
f.cw_mode     = ProtoField.uint16("sercos2.mdt.cw.op_mode", "Operation mode (bits 9-8)", base.DEC,
                    op_mode_names, 0x0300)
f.cw_rtc2     = ProtoField.bool("sercos2.mdt.cw.rtc2", "Real-time control bit 2 (bit 7, S-0-0302)",
                    16, nil, 0x0080)
f.cw_rtc1     = ProtoField.bool("sercos2.mdt.cw.rtc1", "Real-time control bit 1 (bit 6, S-0-0300)",
                    16, nil, 0x0040)
f.cw_element  = ProtoField.uint16("sercos2.mdt.cw.element", "Data block element (bits 5-3)",
                    base.DEC, element_names, 0x0038)
f.cw_last     = ProtoField.bool("sercos2.mdt.cw.last", "Transmission (bit 2)", 16,
                    { "last transmission", "transmission in progress" }, 0x0004)
f.cw_write    = ProtoField.bool("sercos2.mdt.cw.write", "Read/write (bit 1)", 16,
                    { "write service info", "read service info" }, 0x0002)
f.cw_mhs      = ProtoField.uint16("sercos2.mdt.cw.mhs",
                    "Master service transport handshake MHS (bit 0)", base.DEC, nil, 0x0001)

-- AT status word: sercos-telegrams.md, Amplifier Telegram, bits 15-0 (bit 10 is missing from
-- the table and bits 4-3 are "Reserved": shown together as reserved).
local ready_names = {
    [0] = "drive not ready for power-up",
    [1] = "drive ready for power-up",
    [2] = "drive power ready",
    [3] = "drive ready to operate",
}
f.sw          = ProtoField.uint16("sercos2.at.sw", "Status word", base.HEX)
f.sw_ready    = ProtoField.uint16("sercos2.at.sw.ready", "Ready to operate (bits 15-14)", base.DEC,
                    ready_names, 0xC000)
f.sw_shutdown = ProtoField.bool("sercos2.at.sw.shutdown_error",
                    "Drive shutdown error, class 3 diags (bit 13)", 16, nil, 0x2000)
f.sw_c2       = ProtoField.bool("sercos2.at.sw.change_class2", "Change bit for class 2 diags (bit 12)",
                    16, nil, 0x1000)
f.sw_c3       = ProtoField.bool("sercos2.at.sw.change_class3", "Change bit for class 3 diags (bit 11)",
                    16, nil, 0x0800)
f.sw_res      = ProtoField.uint16("sercos2.at.sw.reserved", "Reserved (bits 10, 4-3)", base.HEX,
                    nil, 0x0418)
f.sw_mode     = ProtoField.uint16("sercos2.at.sw.op_mode", "Actual operation mode (bits 9-8)",
                    base.DEC, op_mode_names, 0x0300)
f.sw_rts2     = ProtoField.bool("sercos2.at.sw.rts2", "Real-time status bit 2 (bit 7, S-0-0306)",
                    16, nil, 0x0080)
f.sw_rts1     = ProtoField.bool("sercos2.at.sw.rts1", "Real-time status bit 1 (bit 6, S-0-0304)",
                    16, nil, 0x0040)
f.sw_cmd      = ProtoField.bool("sercos2.at.sw.cmd_change", "Change bit commands (bit 5)", 16,
                    { "changing command status", "no change in command status" }, 0x0020)
f.sw_error    = ProtoField.bool("sercos2.at.sw.error", "Error (bit 2)", 16,
                    { "error in service channel", "no error" }, 0x0004)
f.sw_busy     = ProtoField.bool("sercos2.at.sw.busy", "Busy (bit 1)", 16,
                    { "step in progress", "step finished" }, 0x0002)
f.sw_ahs      = ProtoField.uint16("sercos2.at.sw.ahs",
                    "Master service transport handshake AHS (bit 0)", base.DEC, nil, 0x0001)

local field_list = {}
for _, field in pairs(f) do
    table.insert(field_list, field)
end
sercos2.fields = field_list

local ef_fcs_bad = ProtoExpert.new("sercos2.fcs_bad.expert", "FCS mismatch",
    expert.group.CHECKSUM, expert.severity.ERROR)
local ef_line_error = ProtoExpert.new("sercos2.line_error.expert", "Frame broken on the line",
    expert.group.MALFORMED, expert.severity.ERROR)
local ef_version = ProtoExpert.new("sercos2.version.expert", "Unknown pseudo-header version",
    expert.group.UNDECODED, expert.severity.WARN)
sercos2.experts = { ef_fcs_bad, ef_line_error, ef_version }

-- Preference: the data block length of each record of a broadcast MDT (fixed in phase 2 by the
-- master; the capture does not carry it). 0 = show the message field as one record.
sercos2.prefs.mdt_block_len = Pref.uint("Broadcast MDT data block length",
    0, "Bytes of data block in each record of a broadcast (phase 3/4) MDT; 0 = one record")

-- Dissection --------------------------------------------------------------------------------

local RECORD_HEADER = 4 -- control/status word and service info

local function add_control_word(tree, tvb)
    local t = tree:add_le(f.cw, tvb)
    t:add_le(f.cw_on, tvb)
    t:add_le(f.cw_enable, tvb)
    t:add_le(f.cw_restart, tvb)
    t:add_le(f.cw_res, tvb)
    t:add_le(f.cw_sync, tvb)
    t:add_le(f.cw_mode, tvb)
    t:add_le(f.cw_rtc2, tvb)
    t:add_le(f.cw_rtc1, tvb)
    t:add_le(f.cw_element, tvb)
    t:add_le(f.cw_last, tvb)
    t:add_le(f.cw_write, tvb)
    t:add_le(f.cw_mhs, tvb)
end

local function add_status_word(tree, tvb)
    local t = tree:add_le(f.sw, tvb)
    t:add_le(f.sw_ready, tvb)
    t:add_le(f.sw_shutdown, tvb)
    t:add_le(f.sw_c2, tvb)
    t:add_le(f.sw_c3, tvb)
    t:add_le(f.sw_res, tvb)
    t:add_le(f.sw_mode, tvb)
    t:add_le(f.sw_rts2, tvb)
    t:add_le(f.sw_rts1, tvb)
    t:add_le(f.sw_cmd, tvb)
    t:add_le(f.sw_error, tvb)
    t:add_le(f.sw_busy, tvb)
    t:add_le(f.sw_ahs, tvb)
end

-- One data record at `offset` of `len` bytes inside the message field `tvb`; `is_mdt` picks
-- the control word (MDT) or the status word (AT). Returns the word.
local function add_record(tree, tvb, offset, len, is_mdt, label)
    local rt = tree:add(f.record, tvb(offset, len))
    rt:set_text(string.format("%s, offset %d, %d bytes", label, offset, len))
    rt:add(f.record_off, offset):set_generated()
    local word_tvb = tvb(offset, 2)
    if is_mdt then
        add_control_word(rt, word_tvb)
    else
        add_status_word(rt, word_tvb)
    end
    rt:add_le(f.service, tvb(offset + 2, 2))
    if len > RECORD_HEADER then
        rt:add(f.data_block, tvb(offset + RECORD_HEADER, len - RECORD_HEADER))
    end
    return word_tvb:le_uint()
end

function sercos2.dissector(tvb, pinfo, tree)
    local total = tvb:len()
    if total < HEADER_LEN then
        return 0
    end
    pinfo.cols.protocol = "SERCOS2"
    local root = tree:add(sercos2, tvb(), "SERCOS II telegram")

    -- Pseudo-header.
    local ph = root:add(tvb(0, HEADER_LEN), "Simulator pseudo-header")
    local version = tvb(0, 1):uint()
    local vi = ph:add(f.version, tvb(0, 1))
    if version ~= 1 then
        vi:add_proto_expert_info(ef_version)
    end
    local hlen = tvb(1, 1):uint()
    if hlen < HEADER_LEN then
        hlen = HEADER_LEN
    end
    ph:add(f.header_len, tvb(1, 1))
    local segment = tvb(2, 2):le_uint()
    ph:add_le(f.segment, tvb(2, 2))
    local flags = tvb(4, 1):uint()
    local ft = ph:add(f.flags, tvb(4, 1))
    ft:add(f.origin, tvb(4, 1))
    ft:add(f.fcs_ok, tvb(4, 1))
    ft:add(f.fcs_valid, tvb(4, 1))
    ft:add(f.line_err_fl, tvb(4, 1))
    local line_error = tvb(5, 1):uint()
    ph:add(f.line_error, tvb(5, 1))
    ph:add_le(f.bit_rate, tvb(6, 2))
    ph:add_le(f.fcs_rx, tvb(8, 2))
    ph:add_le(f.fcs_calc, tvb(10, 2))
    ph:add_le(f.reserved, tvb(12, 4))
    ph:add_le(f.time_ps, tvb(16, 8))

    local slave = bit.band(flags, 0x01) ~= 0
    local fcs_ok = bit.band(flags, 0x02) ~= 0
    local info_tail = ""
    if not fcs_ok then
        if line_error == 1 then
            info_tail = string.format(" [FCS BAD rx %04X calc %04X]",
                tvb(8, 2):le_uint(), tvb(10, 2):le_uint())
            root:add_proto_expert_info(ef_fcs_bad)
        else
            info_tail = " [" .. (line_error_names[line_error] or "line error") .. "]"
        end
    end

    if total <= hlen then
        pinfo.cols.info = string.format("seg %d: empty%s", segment, info_tail)
        return total
    end
    local tel = tvb(hlen):tvb()
    local len = tel:len()

    -- A frame that broke off (abort, length errors) is not a whole telegram.
    if line_error > 1 then
        root:add(f.received, tel())
        root:add_proto_expert_info(ef_line_error)
        pinfo.cols.info = string.format("seg %d: %d bytes%s", segment, len, info_tail)
        return total
    end

    -- sercos-telegrams.md, ADR table: the master sends MST (ADR 255, one data byte) and MDT;
    -- slaves send AT.
    local adr = tel(0, 1):uint()
    local kind
    if slave then
        kind = "AT"
    elseif adr == 255 and len == 2 then
        kind = "MST"
    else
        kind = "MDT"
    end
    root:add(f.kind, kind):set_generated()
    root:add(f.adr, tel(0, 1))
    root:append_text(string.format(", %s, ADR %d", kind, adr))

    local info
    if kind == "MST" then
        local byte = tel(1, 1):uint()
        root:add(f.mst_byte, tel(1, 1))
        root:add(f.mst_phase, tel(1, 1))
        root:add(f.mst_other, tel(1, 1))
        info = string.format("MST phase %d", bit.band(byte, 0x07))
    elseif len < 1 + RECORD_HEADER then
        root:add(f.malformed, tel(1))
        info = string.format("%s ADR %d malformed (%d bytes)", kind, adr, len)
    elseif kind == "MDT" then
        local field_len = len - 1
        local block = sercos2.prefs.mdt_block_len
        local msg = tel(1):tvb()
        local cw
        if adr == 255 and block > 0 then
            local record_len = RECORD_HEADER + block
            local offset = 0
            local n = 0
            while offset + record_len <= field_len do
                local w = add_record(root, msg, offset, record_len, true,
                    string.format("Data record %d", n))
                if n == 0 then
                    cw = w
                end
                offset = offset + record_len
                n = n + 1
            end
            if offset < field_len then
                root:add(f.data_block, msg(offset, field_len - offset)):append_text(" (rest)")
            end
        else
            cw = add_record(root, msg, 0, field_len, true, "Data record")
        end
        info = string.format("MDT ADR %d CW 0x%04X", adr, cw or 0)
    else
        local sw = add_record(root, tel(1):tvb(), 0, len - 1, false, "Data record")
        info = string.format("AT ADR %d SW 0x%04X", adr, sw)
    end
    pinfo.cols.info = string.format("seg %d: %s%s", segment, info, info_tail)
    return total
end

-- Wireshark 4.2 renamed the `wtap` table to `wtap_encaps`; accept both.
local encaps = wtap_encaps or wtap
DissectorTable.get("wtap_encap"):add(encaps.USER0, sercos2)
