-- ptpcert.lua: a Wireshark dissector for the captures of ptpcert (pcap, link type
-- LINKTYPE_RTAC_SERIAL 250): the point-to-point procedures of the SIMATIC CP 341,
-- 3964/3964R, RK 512 on 3964(R), and the ASCII driver.
--
-- Install: `ptpcert capture --wireshark-plugin install` (copies this file into the personal
-- Lua plugin folder, ~/.local/lib/wireshark/plugins/), or for one run:
--   tshark -X lua_script:ptpcert.lua -r run.pcap
-- The capture format is specified in ptpcert's docs/capture-formats.md; this dissector in
-- docs/wireshark.md.
--
-- How it works. Each record of the capture holds the bytes one station put on the line at
-- one instant (in a run, usually one byte). A 3964(R) block or an ASCII frame spans many
-- records, so the dissector runs a state machine per direction over the records in order,
-- on the first pass (pinfo.visited false), and stores what each record completes under its
-- frame number; every later dissection (tshark -2's second pass, clicks in Wireshark) shows
-- what was stored. A block shows on the record of its last character (the BCC, or ETX
-- without BCC); an ASCII frame on the record of its end character or its last character of
-- a fixed length, and a frame that the character delay time ends (criterion CDT) on the
-- first record after the CDT expired. So a single pass and tshark -2 give the same fields.
--
-- What it decodes comes from the capture: the start record's note "procedure: ..." and the
-- marks (or the note of a one-case capture) "parameters {JSON}" that carry each case's
-- settings (3964 or 3964R, the RK 512 link, the ASCII end criterion, end characters, fixed
-- length, CDT, XON/XOFF). A capture that says neither (another recorder, an old capture) is
-- decoded as the preference "Procedure" says (Edit > Preferences > Protocols > PTPCERT).

local ptp = Proto("ptpcert", "ptpcert point-to-point link (3964/3964R, RK 512, ASCII)")

local bxor = bit32 and bit32.bxor or bit.bxor
local band = bit32 and bit32.band or bit.band
local rshift = bit32 and bit32.rshift or bit.rshift

local STX, DLE, ETX, NAK = 0x02, 0x10, 0x03, 0x15

-- RK 512 (the manual's §2.2.3, Table 2-1; Table 8-3)
local RK_COMMANDS = { [0x41] = "A: SEND to a DB", [0x4F] = "O: SEND to a DX", [0x45] = "E: FETCH" }
local RK_TYPES = {
    [0x44] = "D: data block (DB)", [0x58] = "X: extended data block (DX)", [0x45] = "E: input bytes",
    [0x41] = "A: output bytes", [0x4D] = "M: flag bytes", [0x54] = "T: timers", [0x5A] = "Z: counters",
}
local RK_WORD_TYPES = { [0x44] = true, [0x58] = true, [0x54] = true, [0x5A] = true }
local REATEL = {
    [0x00] = "no error",
    [0x0A] = "partner: source/destination type not permitted, memory error in the partner PLC, error "
        .. "notifying CP/CPU, or partner PLC in STOP (0905H)",
    [0x0C] = "memory/area access error: area missing or too short, start address too high, coordination "
        .. "flag or CPU number invalid (0902H)",
    [0x10] = "header error in byte 1 or byte 4 (090BH)",
    [0x12] = "request type not permitted (0904H)",
    [0x14] = "DB/DX does not exist, is too short or has an impermissible number; FETCH source area "
        .. "exceeded (0903H)",
    [0x16] = "header error in byte 3, the command letter (090AH)",
    [0x2A] = "partner not (yet) restarted: CPU STOP, startup, re-parameterisation (090DH)",
    [0x32] = "DB/DX locked by coordination flag (0909H)",
    [0x34] = "length error: invalid length, data count not as in the header, FETCH with data (090CH)",
    [0x36] = "synchronisation or frame sequence error (0908H)",
}
local function reatel_meaning(v)
    return REATEL[v] or "unknown error number (090EH)"
end

local f = {
    seat = ProtoField.string("ptpcert.seat", "Seat"),
    char = ProtoField.string("ptpcert.char", "Character"),
    cond = ProtoField.string("ptpcert.condition", "Line condition"),
    mark = ProtoField.string("ptpcert.mark", "Mark"),
    case = ProtoField.string("ptpcert.case", "Case"),
    note = ProtoField.string("ptpcert.note", "Capture header"),
    block = ProtoField.bytes("ptpcert.block", "3964(R) block data (DLE undoubled)"),
    block_seat = ProtoField.string("ptpcert.block.seat", "Sent by seat"),
    block_len = ProtoField.uint16("ptpcert.block.length", "Data length"),
    block_end = ProtoField.string("ptpcert.block.end", "Block end"),
    bcc = ProtoField.uint8("ptpcert.block.bcc", "BCC", base.HEX),
    bcc_calc = ProtoField.uint8("ptpcert.block.bcc_computed", "BCC computed", base.HEX),
    bcc_ok = ProtoField.bool("ptpcert.block.bcc_ok", "BCC good"),
    rk_kind = ProtoField.string("ptpcert.rk512.kind", "RK 512 telegram"),
    rk_b1 = ProtoField.uint8("ptpcert.rk512.byte1", "Byte 1, frame ID (00 first, FF continuation)", base.HEX),
    rk_b2 = ProtoField.uint8("ptpcert.rk512.byte2", "Byte 2, frame ID", base.HEX),
    rk_cmd = ProtoField.uint8("ptpcert.rk512.command", "Byte 3, command", base.HEX, RK_COMMANDS),
    rk_type = ProtoField.uint8("ptpcert.rk512.type", "Byte 4, data type", base.HEX, RK_TYPES),
    rk_hi = ProtoField.uint8("ptpcert.rk512.address_high", "Byte 5, DB/DX number (address high)"),
    rk_lo = ProtoField.uint8("ptpcert.rk512.address_low", "Byte 6, DW number (address low)"),
    rk_len = ProtoField.uint16("ptpcert.rk512.length", "Bytes 7-8, length"),
    rk_unit = ProtoField.string("ptpcert.rk512.length_unit", "Length unit"),
    rk_cf = ProtoField.uint8("ptpcert.rk512.cf_byte", "Byte 9, coordination flag byte (FF none)", base.HEX),
    rk_cpu = ProtoField.uint8("ptpcert.rk512.cpu", "Byte 10 bits 4-7, CPU number (F none)", base.HEX),
    rk_bit = ProtoField.uint8("ptpcert.rk512.cf_bit", "Byte 10 bits 0-3, coordination flag bit (F none)", base.HEX),
    rk_reatel = ProtoField.uint8("ptpcert.rk512.reatel", "Byte 4, REATEL (error number)", base.HEX),
    rk_meaning = ProtoField.string("ptpcert.rk512.reatel_meaning", "REATEL meaning (Table 8-3)"),
    rk_data = ProtoField.bytes("ptpcert.rk512.data", "User data"),
    a_frame = ProtoField.bytes("ptpcert.ascii.frame", "ASCII frame"),
    a_seat = ProtoField.string("ptpcert.ascii.seat", "Sent by seat"),
    a_end = ProtoField.string("ptpcert.ascii.end", "Frame end"),
    a_flow = ProtoField.string("ptpcert.ascii.flow", "Flow control"),
}
ptp.fields = f

local e = {
    bcc_bad = ProtoExpert.new("ptpcert.block.bcc_bad", "BCC wrong", expert.group.CHECKSUM, expert.severity.ERROR),
    logic = ProtoExpert.new("ptpcert.block.logic_error", "DLE followed by neither DLE nor ETX",
        expert.group.MALFORMED, expert.severity.WARN),
    cut = ProtoExpert.new("ptpcert.block.incomplete", "block not completed", expert.group.SEQUENCE,
        expert.severity.NOTE),
    rk_short = ProtoExpert.new("ptpcert.rk512.short", "RK 512 frame too short", expert.group.MALFORMED,
        expert.severity.WARN),
    rk_error = ProtoExpert.new("ptpcert.rk512.error", "RK 512 response with an error number",
        expert.group.RESPONSE_CODE, expert.severity.NOTE),
    a_cut = ProtoExpert.new("ptpcert.ascii.incomplete", "ASCII frame without its end", expert.group.SEQUENCE,
        expert.severity.NOTE),
    char_error = ProtoExpert.new("ptpcert.char_error", "character received with an error",
        expert.group.MALFORMED, expert.severity.WARN),
}
ptp.experts = e

-- Preferences: what to decode when the capture does not say (or to override it).
local PROC_AUTO, PROC_3964R, PROC_3964, PROC_RK_R, PROC_RK, PROC_ASCII = 0, 1, 2, 3, 4, 5
ptp.prefs.procedure = Pref.enum("Procedure", PROC_AUTO,
    "auto: what the capture says (ptpcert writes it); otherwise this procedure for every record", {
        { 1, "auto (from the capture)", PROC_AUTO }, { 2, "3964R", PROC_3964R }, { 3, "3964", PROC_3964 },
        { 4, "RK 512 on 3964R", PROC_RK_R }, { 5, "RK 512 on 3964", PROC_RK }, { 6, "ASCII driver", PROC_ASCII },
    }, false)
ptp.prefs.end_chars = Pref.string("ASCII end characters", "03",
    "with procedure ASCII set here: end characters in hex (one or two, e.g. 03 or 0D 0A; empty: "
    .. "frames end at the CDT)")
ptp.prefs.cdt_ms = Pref.uint("ASCII character delay time (ms)", 20, "with procedure ASCII set here")
ptp.prefs.xon_xoff = Pref.bool("ASCII XON/XOFF", true, "with procedure ASCII set here: 11 and 13 are XON and XOFF")

-- ------------------------------------------------------------------ state of the first pass

local st          -- the state machines (reset when a file is opened)
local stored = {} -- frame number -> what that record shows

local function new_dir()
    return { state = "idle", raw = {}, data = {}, errors = 0, awaiting_ack = false, frame = {}, last_us = nil }
end

local function new_state()
    return { first = true, cfg = { family = nil, bcc = true, criterion = "cdt", end_chars = {}, fixed = nil,
        cdt_us = nil, flow = false, xon = 0x11, xoff = 0x13 }, char_us = 0, dirs = { a = new_dir(), b = new_dir() } }
end

function ptp.init()
    st = new_state()
    stored = {}
end

local function other(seat) return seat == "a" and "b" or "a" end

local function parse_params(s)
    local t = {}
    for k, v in s:gmatch('"([%w_]+)":(%b[])') do
        local list = {}
        for n in v:gmatch("%-?%d+") do list[#list + 1] = tonumber(n) end
        t[k] = list
    end
    for k, v in s:gmatch('"([%w_]+)":"([^"]*)"') do t[k] = v end
    for k, v in s:gmatch('"([%w_]+)":([%-%w%.]+)') do
        if t[k] == nil then
            if v == "true" then t[k] = true elseif v == "false" then t[k] = false else t[k] = tonumber(v) end
        end
    end
    return t
end

-- A case's parameters (a ptpcert results object's "params") into the decoder's settings.
local function apply_params(cfg, p)
    if p.link ~= nil then
        cfg.family, cfg.bcc = "rk512", p.link ~= "3964"
    elseif p.procedure == "3964" or p.procedure == "3964R" then
        cfg.family, cfg.bcc = "3964", p.procedure == "3964R"
    elseif p.end_criterion ~= nil then
        cfg.family = "ascii"
        cfg.criterion = p.end_criterion
        cfg.end_chars = (p.end_criterion == "end_chars" and p.end_chars) or {}
        cfg.fixed = (p.end_criterion == "fixed_length" and p.fixed_length) or nil
        cfg.flow = p.flow_control == "xon_xoff"
        cfg.xon, cfg.xoff = p.xon or 0x11, p.xoff or 0x13
    end
    if p.cdt_ms then cfg.cdt_us = p.cdt_ms * 1000 end
end

local function apply_procedure_note(cfg, title)
    if cfg.family then return end
    if title == "RK 512" then cfg.family = "rk512"
    elseif title == "ASCII driver" then cfg.family = "ascii"
    elseif title:find("3964") then cfg.family = "3964" end
end

-- The settings in force: the preference when it names a procedure, else the capture's.
local function settings()
    local pref = ptp.prefs.procedure
    if pref == PROC_AUTO then return st.cfg end
    if pref == PROC_ASCII then
        local ends = {}
        for h in ptp.prefs.end_chars:gmatch("%x%x") do ends[#ends + 1] = tonumber(h, 16) end
        return { family = "ascii", criterion = #ends > 0 and "end_chars" or "cdt", end_chars = ends,
            cdt_us = ptp.prefs.cdt_ms * 1000, flow = ptp.prefs.xon_xoff, xon = 0x11, xoff = 0x13 }
    end
    return { family = (pref == PROC_RK_R or pref == PROC_RK) and "rk512" or "3964",
        bcc = pref == PROC_3964R or pref == PROC_RK_R }
end

-- ------------------------------------------------------------------ 3964/3964R

local function bytes_hex(list)
    local out = {}
    for i, b in ipairs(list) do out[i] = string.format("%02X", b) end
    return table.concat(out)
end

local function finish_block(seat, items, ending, bcc)
    local d = st.dirs[seat]
    local calc = 0
    for _, b in ipairs(d.raw) do calc = bxor(calc, b) end
    items[#items + 1] = { kind = "block", seat = seat, data = d.data, ending = ending, bcc = bcc, calc = calc,
        errors = d.errors, rk = settings().family == "rk512" }
    d.awaiting_ack = ending == "DLE ETX"
    d.state, d.raw, d.data, d.errors = "idle", {}, {}, 0
end

local function abort_block(seat, items, why)
    local d = st.dirs[seat]
    if d.state == "block" or d.state == "dle" or d.state == "bcc" then
        finish_block(seat, items, why, nil)
        st.dirs[seat].awaiting_ack = false
    elseif d.state == "setup" then
        d.state = "idle"
    end
end

-- Any character but NAK from the receiver during the partner's data phase: the sender stops
-- the block (and, after the CDT, sends NAK and starts again with STX); §2.2.2 Sending data.
local function interrupts(seat, items)
    local o = st.dirs[other(seat)]
    if o.state == "block" or o.state == "dle" then
        abort_block(other(seat), items, "interrupted by the partner")
        return true
    end
    return false
end

local function byte_3964(seat, b, cfg, items)
    local d, o = st.dirs[seat], st.dirs[other(seat)]
    local label
    if b ~= NAK and interrupts(seat, items) then
        return byte_3964(seat, b, cfg, items) .. " (interrupts the partner's block)"
    end
    if d.state == "block" then
        d.raw[#d.raw + 1] = b
        if b == DLE then
            d.state, label = "dle", "DLE"
        else
            d.data[#d.data + 1], label = b, "data"
        end
    elseif d.state == "dle" then
        d.raw[#d.raw + 1] = b
        if b == DLE then
            d.data[#d.data + 1], d.state, label = DLE, "block", "DLE (doubled: data 10)"
        elseif b == ETX then
            label = "ETX (end of block)"
            if cfg.bcc then d.state = "bcc" else finish_block(seat, items, "DLE ETX", nil) end
        else
            label = "after DLE: logic error"
            finish_block(seat, items, "logic error", nil)
            d.awaiting_ack = false
        end
    elseif d.state == "bcc" then
        label = "BCC"
        finish_block(seat, items, "DLE ETX", b)
    elseif b == STX then
        if o.state == "setup" then label = "STX (both stations: initialization conflict)"
        else label = "STX (connection setup)" end
        d.state, d.awaiting_ack = "setup", false
    elseif b == DLE then
        if o.state == "setup" then
            label = "DLE (ready to receive)"
            o.state, o.raw, o.data, o.errors = "block", {}, {}, 0
            if d.state == "setup" then d.state = "idle" end   -- the low-priority station yields
        elseif o.awaiting_ack then
            label, o.awaiting_ack = "DLE (block accepted)", false
        else
            label = "DLE"
        end
    elseif b == NAK then
        if o.state == "setup" then
            label, o.state = "NAK (connection refused)", "idle"
        elseif o.state == "block" or o.state == "dle" or o.state == "bcc" then
            label = "NAK (block aborted by the receiver)"
            abort_block(other(seat), items, "aborted by NAK")
        elseif o.awaiting_ack then
            label, o.awaiting_ack = "NAK (block refused)", false
        else
            label = "NAK"
        end
        if d.state == "setup" then d.state = "idle" end
    elseif d.state == "setup" then
        label = "character before the partner's DLE"
    else
        label = "character outside a block"
    end
    return label
end

-- ------------------------------------------------------------------ ASCII driver

local function finish_frame(seat, items, ending)
    local d = st.dirs[seat]
    if #d.frame > 0 then
        items[#items + 1] = { kind = "aframe", seat = seat, data = d.frame, ending = ending, errors = d.errors }
    end
    d.frame, d.errors = {}, 0
end

-- Frames the character delay time ended before the record at time t (or all, t nil).
local function expire(t, items, why)
    local cfg = settings()
    if cfg.family ~= "ascii" then return end
    for _, seat in ipairs({ "a", "b" }) do
        local d = st.dirs[seat]
        if #d.frame > 0 and d.last_us and not (t and d.held) then
            local expired = cfg.cdt_us and t and t - d.last_us - st.char_us >= cfg.cdt_us
            if expired or t == nil then
                local complete = cfg.criterion == "cdt" and (expired or false)
                finish_frame(seat, items, complete and "CDT expired" or
                    (expired and "CDT expired before the end: incomplete" or why))
            end
        end
    end
end

local function ends_with(list, tail)
    if #tail == 0 or #list < #tail then return false end
    for i = 1, #tail do
        if list[#list - #tail + i] ~= tail[i] then return false end
    end
    return true
end

local function byte_ascii(seat, b, t, cfg, items)
    local d, o = st.dirs[seat], st.dirs[other(seat)]
    -- XOFF holds the partner's sending: its CDT does not run until XON (from then on)
    if cfg.flow and b == cfg.xon then
        if o.held and o.last_us then o.last_us = t end
        o.held = false
        return "XON", true
    end
    if cfg.flow and b == cfg.xoff then o.held = true; return "XOFF", true end
    d.frame[#d.frame + 1] = b
    d.last_us = t
    if cfg.criterion == "end_chars" and ends_with(d.frame, cfg.end_chars) then
        finish_frame(seat, items, "end character" .. (#cfg.end_chars > 1 and "s " or " ") .. bytes_hex(cfg.end_chars))
        return "end character"
    elseif cfg.criterion == "fixed_length" and cfg.fixed and #d.frame >= cfg.fixed then
        finish_frame(seat, items, "fixed length " .. cfg.fixed)
    end
    return "data"
end

-- ------------------------------------------------------------------ records

local function reset_all(items, why)
    for _, seat in ipairs({ "a", "b" }) do
        abort_block(seat, items, why)
        st.dirs[seat].awaiting_ack = false
    end
    expire(nil, items, why)
    st.dirs = { a = new_dir(), b = new_dir() }
end

local function read_start(text, items)
    for line in text:gmatch("[^\n]+") do
        local key, value = line:match("^(%w+):%s*(.*)$")
        if key then
            items[#items + 1] = { kind = "note", text = line }
            items.start = true
            if key == "note" and value:match("^procedure: ") then
                apply_procedure_note(st.cfg, value:sub(12))
            elseif key == "note" and value:match("^parameters ") then
                apply_params(st.cfg, parse_params(value))
            elseif key == "timing" then
                local ct = value:match("char_time=([%d%.]+)")
                if ct then st.char_us = tonumber(ct) * 1e6 end
            elseif key == "line" and st.char_us == 0 then
                local baud, bits, par, stop = value:match("^(%d+)%s+(%d)(%a)(%d)")
                if baud then
                    local n = 1 + tonumber(bits) + (par:upper() == "N" and 0 or 1) + tonumber(stop)
                    st.char_us = n * 1e6 / tonumber(baud)
                end
            end
        end
    end
end

local EV_SEAT = { [1] = "a", [3] = "a", [2] = "b", [4] = "b" }
local COND = { [5] = "data lost by the recorder", [7] = "framing error", [8] = "parity error", [9] = "BREAK",
    [10] = "overrun" }

local function first_pass(tvb)
    local items = {}
    local len = tvb:len()
    if len < 12 then return items end
    local ev, footer = tvb(8, 1):uint(), tvb(10, 2):uint()
    local t = tvb(0, 4):uint() * 1000000 + tvb(4, 4):uint()
    local payload = len > 12 and tvb:raw(12, len - 12) or ""
    if st.first then
        st.first = false
        if ev == 0 and payload:sub(1, 17) == "ptpcert-capture 1" then
            read_start(payload:sub(18), items)
            return items
        end
    end
    expire(t, items, nil)
    if ev == 0 and payload:sub(1, 13) == "ptpcert-mark\n" then
        local text = payload:sub(14)
        if text:match("^case ") then reset_all(items, "the case ends") end
        if text:match("^parameters ") then apply_params(st.cfg, parse_params(text)) end
        items[#items + 1] = { kind = "mark", text = text }
        return items
    end
    if ev == 6 then
        reset_all(items, "the capture ends")
        return items
    end
    local seat = EV_SEAT[ev] or (footer == 1 and "a") or (footer == 2 and "b") or "b"
    items.seat = seat
    if COND[ev] and ev ~= 7 and ev ~= 8 then
        items[#items + 1] = { kind = "cond", label = COND[ev] }
        if ev == 9 then abort_block(seat, items, "BREAK"); st.dirs[seat].frame = {} end
        return items
    end
    if ev == 7 or ev == 8 then
        items[#items + 1] = { kind = "cond", label = COND[ev] }
        st.dirs[seat].errors = st.dirs[seat].errors + 1
        local fam = settings().family
        if #payload == 0 and (fam == "3964" or fam == "rk512") then interrupts(seat, items) end
    elseif EV_SEAT[ev] == nil then
        return items
    end
    local cfg = settings()
    for i = 1, #payload do
        local b = payload:byte(i)
        local label, flow
        if cfg.family == "ascii" then
            label, flow = byte_ascii(seat, b, t, cfg, items)
        elseif cfg.family then
            label = byte_3964(seat, b, cfg, items)
        end
        if label then items[#items + 1] = { kind = "char", off = i - 1, label = label, flow = flow } end
    end
    return items
end

-- ------------------------------------------------------------------ the tree

local function add_rk512(tree, rtvb, data)
    local n = rtvb:len()
    if n < 4 then
        local it = tree:add(f.rk_kind, rtvb(), "too short (" .. n .. " bytes; 4 at least)")
        it:add_proto_expert_info(e.rk_short)
        return "RK 512 frame too short"
    end
    local b1, b3 = data[1], data[3]
    local kind, summary
    local sub
    if b3 == 0 then
        kind = (b1 == 0xFF and "continuation response") or (b1 == 0 and "response") or "response (byte 1 invalid)"
        sub = tree:add(f.rk_kind, rtvb(0, 4), kind)
        sub:add(f.rk_b1, rtvb(0, 1)); sub:add(f.rk_b2, rtvb(1, 1)); sub:add(f.rk_cmd, rtvb(2, 1))
        sub:add(f.rk_reatel, rtvb(3, 1))
        sub:add(f.rk_meaning, rtvb(3, 1), reatel_meaning(data[4]))
        if data[4] ~= 0 then sub:add_proto_expert_info(e.rk_error, "REATEL " .. string.format("%02X", data[4])
            .. ": " .. reatel_meaning(data[4])) end
        summary = string.format("RK 512 %s, REATEL %02X", kind, data[4])
        if n > 4 then sub:add(f.rk_data, rtvb(4)); summary = summary .. ", " .. (n - 4) .. " data bytes" end
        return summary
    end
    local first = b1 ~= 0xFF
    local hlen = first and 10 or 4
    kind = first and (b1 == 0 and "command" or "command (byte 1 invalid)") or "continuation command"
    if n < hlen then
        sub = tree:add(f.rk_kind, rtvb(), kind .. ", too short (" .. n .. " bytes; " .. hlen .. " at least)")
        sub:add_proto_expert_info(e.rk_short)
        return "RK 512 " .. kind .. " too short"
    end
    sub = tree:add(f.rk_kind, rtvb(0, hlen), kind)
    sub:add(f.rk_b1, rtvb(0, 1)); sub:add(f.rk_b2, rtvb(1, 1))
    sub:add(f.rk_cmd, rtvb(2, 1)); sub:add(f.rk_type, rtvb(3, 1))
    local cmd = ({ [0x41] = "SEND", [0x4F] = "SEND", [0x45] = "FETCH" })[b3] or string.format("command %02X", b3)
    summary = "RK 512 " .. kind .. ": " .. cmd
    if first then
        local length = data[7] * 256 + data[8]
        local unit = RK_WORD_TYPES[data[4]] and "words" or "bytes"
        sub:add(f.rk_hi, rtvb(4, 1)); sub:add(f.rk_lo, rtvb(5, 1))
        sub:add(f.rk_len, rtvb(6, 2)); sub:add(f.rk_unit, rtvb(6, 2), unit)
        sub:add(f.rk_cf, rtvb(8, 1))
        sub:add(f.rk_cpu, rtvb(9, 1), rshift(data[10], 4))
        sub:add(f.rk_bit, rtvb(9, 1), band(data[10], 0x0F))
        if data[4] == 0x44 or data[4] == 0x58 then
            summary = summary .. string.format(" %s %d DW %d", data[4] == 0x44 and "DB" or "DX", data[5], data[6])
        else
            summary = summary .. string.format(" %s address %d", string.char(data[4]), data[5] * 256 + data[6])
        end
        summary = summary .. string.format(", %d %s", length, unit)
    end
    if n > hlen then
        sub:add(f.rk_data, rtvb(hlen))
        summary = summary .. ", " .. (n - hlen) .. " data bytes"
    end
    return summary
end

local function add_block(tree, tvb, it)
    local label = "block " .. #it.data .. " bytes"
    local sub = tree:add(ptp, tvb(), "3964(R) block from seat " .. it.seat)
    local rtvb
    if #it.data > 0 then
        rtvb = ByteArray.new(bytes_hex(it.data)):tvb("3964(R) block, seat " .. it.seat)
        sub:add(f.block, rtvb())
    end
    sub:add(f.block_seat, it.seat)
    sub:add(f.block_len, #it.data):set_generated()
    local endit = sub:add(f.block_end, it.ending)
    if it.ending ~= "DLE ETX" then
        endit:add_proto_expert_info(it.ending == "logic error" and e.logic or e.cut)
        label = label .. " (" .. it.ending .. ")"
    end
    if it.bcc then
        sub:add(f.bcc, it.bcc)
        sub:add(f.bcc_calc, it.calc):set_generated()
        local okit = sub:add(f.bcc_ok, it.bcc == it.calc)
        okit:set_generated()
        if it.bcc ~= it.calc then
            okit:add_proto_expert_info(e.bcc_bad, string.format("BCC wrong: %02X on the line, %02X computed",
                it.bcc, it.calc))
            label = label .. ", BCC wrong"
        else
            label = label .. ", BCC good"
        end
    end
    if it.errors > 0 then sub:add_proto_expert_info(e.char_error) end
    if it.rk and it.ending == "DLE ETX" and rtvb then
        label = label .. "; " .. add_rk512(sub, rtvb, it.data)
    end
    return label
end

local function add_frame(tree, tvb, it)
    local sub = tree:add(ptp, tvb(), "ASCII frame from seat " .. it.seat)
    local rtvb = ByteArray.new(bytes_hex(it.data)):tvb("ASCII frame, seat " .. it.seat)
    sub:add(f.a_frame, rtvb())
    sub:add(f.a_seat, it.seat)
    local endit = sub:add(f.a_end, it.ending)
    if it.ending:find("incomplete") or it.ending:find("ends") then endit:add_proto_expert_info(e.a_cut) end
    local label = "ASCII frame " .. #it.data .. " bytes (" .. it.ending .. ")"
    if it.errors > 0 then
        sub:add_proto_expert_info(e.char_error)
        label = label .. ", with a character error"
    end
    return label
end

local function render(tvb, pinfo, tree, items)
    local root = tree:add(ptp, tvb())
    local info = {}
    if items.seat then root:add(f.seat, items.seat) end
    local units = {}
    local data_run
    for _, it in ipairs(items) do
        if it.kind == "block" or it.kind == "aframe" then
            units[#units + 1] = it
        elseif it.kind == "note" then
            root:add(f.note, it.text)
        elseif it.kind == "mark" then
            root:add(f.mark, it.text)
            local id = it.text:match("^case (%S+)")
            if id then root:add(f.case, id) end
            info[#info + 1] = it.text:sub(1, 80)
        elseif it.kind == "cond" then
            root:add(f.cond, it.label)
            info[#info + 1] = it.label
        elseif it.kind == "char" then
            local r = tvb(12 + it.off, 1)
            root:add(it.flow and f.a_flow or f.char, r, it.label)
            local hex = string.format("%02X", r:uint())
            if it.label ~= "data" then
                info[#info + 1] = it.label
            elseif data_run then          -- data bytes in a row: one "data .." entry
                info[data_run] = info[data_run] .. " " .. hex
            else
                info[#info + 1] = "data " .. hex
                data_run = #info
            end
            if it.label ~= "data" then data_run = nil end
        end
    end
    for _, it in ipairs(units) do
        info[#info + 1] = (it.kind == "block" and add_block or add_frame)(root, tvb, it)
    end
    if #items > 0 then
        pinfo.cols.protocol = "ptpcert"
        local head = (items.seat and (items.seat .. ": ")) or (items.start and "capture header: ") or ""
        pinfo.cols.info = head .. table.concat(info, "; ")
    end
end

local rtacser = Dissector.get("rtacser")

function ptp.dissector(tvb, pinfo, tree)
    rtacser:call(tvb, pinfo, tree)
    if not pinfo.visited then
        if st == nil then ptp.init() end
        stored[pinfo.number] = first_pass(tvb)
    end
    local items = stored[pinfo.number]
    if items then render(tvb, pinfo, tree, items) end
end

DissectorTable.get("wtap_encap"):add(wtap_encaps.RTAC_SERIAL, ptp)
