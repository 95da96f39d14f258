`timescale 1ns/1ps
// window_unit_tb: a self-checking Icarus Verilog testbench for window_unit
// (hdl/verilog/window_unit.v), for any WIDTH x HEIGHT x PIXEL_BITS the unit accepts.
//
//   iverilog -g2012 -o tb.vvp -P window_unit_tb.WIDTH=640 -P window_unit_tb.HEIGHT=480 \
//       -P window_unit_tb.PIXEL_BITS=10 -P window_unit_tb.SEED=1 \
//       hdl/verilog/tb/window_unit_tb.v hdl/verilog/window_unit.v
//   vvp -n tb.vvp            (add +verbose to print each scenario as it starts)
//
// scripts/icarus-check.sh runs it over a list of sizes; docs/icarus-testbench.md explains it.
//
// Four jobs, each in its own section below:
//   camera   drives a raster whose pixel values identify the pixel (frame, x, y), with random
//            line/frame blanking, random pixel_valid gaps (or pixel_valid tied high), lines
//            longer than WIDTH and frames longer than HEIGHT;
//   writer   the processor: writes coordinate sets over the four-phase handshake and checks
//            that coord_ready rises within 4 clocks of the strobe and falls within 4 of its end;
//   model    the reference: from the contract alone (not from the RTL) decides which set each
//            frame arms and, pixel by pixel as the camera sends them, which must come out and
//            when; it also says what coord_error must be;
//   checker  compares the unit's outputs with the model on every clock and stops at the first
//            difference with $fatal (a non-zero exit from vvp).
// The scenarios at the end drive the four through the cases the contract names.
//
// Time: the pixel clock has period 10. The testbench drives every input at a falling
// edge and samples every output at a falling edge, so nothing races the unit's rising-edge
// logic. "clock n" in messages is the n-th rising edge (`cyc`); inputs driven while cyc == n
// are seen by the unit on edge n+1, and a pixel seen on edge n+1 must be strobed on edge
// n+LATENCY (the contract: it leaves 2 clock edges after it was on the input). A set whose last
// byte is taken on edge s (coord_ready rises on it) arms the first frame whose fval is first
// seen high on edge s+ARM_MARGIN or later (the contract in window_unit.v's header: s+1).
`default_nettype none

module window_unit_tb #(
    parameter integer WIDTH = 256,        // the unit's parameters (16..4096, 16..4096, 8..16)
    parameter integer HEIGHT = 256,
    parameter integer PIXEL_BITS = 8,
    parameter integer SEED = 1,           // seeds every random choice: the same seed, the same run
    parameter integer RANDOM_FRAMES = 16, // frames with random windows after the directed scenarios
    parameter integer FULL_FRAMES = 1,    // frames sent whole (HEIGHT lines of WIDTH pixels) with a full-frame window
    parameter integer DENSE_MAX = 20000,  // frames of up to this many pixels are always sent whole; larger sensors
                                          // get short lines outside a band of full-length lines around the window
    parameter integer BAND_ROWS = 40,     // most rows of a random window on a sensor larger than DENSE_MAX
    parameter integer HB_MIN = 2,         // clocks of lval low between lines
    parameter integer HB_MAX = 10,
    parameter integer FP_MIN = 2,         // clocks from fval rising to the first lval (most: HB_MAX)
    parameter integer BP_MAX = 6,         // clocks from the last line's end to fval falling (from 0)
    parameter integer LATENCY = 2,        // a pixel on the input while cyc == n is strobed on edge n+LATENCY
    parameter integer ARM_MARGIN = 1      // a set whose last byte is taken on edge s arms a frame whose fval
                                          // is first seen on edge s+ARM_MARGIN or later
) ();
    // With WIDTH and HEIGHT <= 256 a set is 4 one-byte coordinates, otherwise 4 two-byte ones.
    localparam integer WIDE = (WIDTH > 256 || HEIGHT > 256) ? 1 : 0;
    localparam integer NBYTES = WIDE ? 8 : 4;
    localparam integer CMAX = WIDE ? 65535 : 255;       // the largest coordinate a set can carry
    localparam integer BIG = (WIDTH * HEIGHT > DENSE_MAX) ? 1 : 0;

    // ---------------------------------------------------------------------------------------
    // The unit under test
    // ---------------------------------------------------------------------------------------
    reg clock = 1'b0;
    always #5 clock = ~clock;
    integer cyc = 0;                 // rising edges so far
    always @(posedge clock) cyc <= cyc + 1;

    reg                   fval = 1'b0, lval = 1'b0, pixel_valid = 1'b0, reset = 1'b0;
    reg  [PIXEL_BITS-1:0] pixel = {PIXEL_BITS{1'b0}};
    reg                   coord_strobe = 1'b0, decimate = 1'b0;
    reg             [7:0] coord_data = 8'd0;
    wire                  coord_ready, pixel_strobe, coord_error;
    wire [PIXEL_BITS-1:0] pixel_out;

    window_unit #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .PIXEL_BITS(PIXEL_BITS)) dut (
        .clock(clock), .fval(fval), .lval(lval), .pixel(pixel),
        .coord_strobe(coord_strobe), .coord_data(coord_data), .coord_ready(coord_ready),
        .decimate(decimate), .pixel_strobe(pixel_strobe), .pixel_out(pixel_out),
        .coord_error(coord_error), .pixel_valid(pixel_valid), .reset(reset),
        .armed(), .window_done(), .set_accepted());

    // ---------------------------------------------------------------------------------------
    // Helpers
    // ---------------------------------------------------------------------------------------
    integer seed = SEED;
    reg verbose = 1'b0;

    // A number in lo..hi, from the one seeded stream.
    function integer rnd(input integer lo, input integer hi);
        begin
            if (hi <= lo) rnd = lo;
            else rnd = lo + ({$random(seed)} % (hi - lo + 1));
        end
    endfunction

    // True with probability pct percent.
    function chance(input integer pct);
        chance = rnd(0, 99) < pct;
    endfunction

    function integer min2(input integer a, input integer b);
        min2 = a < b ? a : b;
    endfunction

    function integer max2(input integer a, input integer b);
        max2 = a > b ? a : b;
    endfunction

    // The value the camera sends for pixel (x, y) of frame f: different for neighbouring
    // columns, rows and frames, so a pixel delivered from the wrong place or the wrong clock
    // shows as a wrong value (the high bits are folded in, so wide columns differ too).
    function [PIXEL_BITS-1:0] pixel_value(input integer f, input integer x, input integer y);
        reg [31:0] v;
        begin
            v = x + 157 * y + 6007 * f;
            pixel_value = v ^ (v >> PIXEL_BITS) ^ (v >> (2 * PIXEL_BITS));
        end
    endfunction

    // Wait n clocks (driving nothing new).
    task automatic idle(input integer n);
        begin
            repeat (n) @(negedge clock);
        end
    endtask

    // ---------------------------------------------------------------------------------------
    // Model: the contract, from the camera's and the writer's side only
    // ---------------------------------------------------------------------------------------
    // Sets are numbered from 1 in the order the writer completes them; 0 is "no set".
    integer n_sets = 0;
    // Valid sets not yet armed by a frame, oldest first (p_n of them): a frame arms the latest
    // one completed in time for it and drops the older ones; any completed too late for it
    // wait for the next frame. p_done is the edge a set's last byte was taken on.
    localparam integer PN = 4;
    integer p_n = 0;
    integer p_xmin [0:PN-1], p_xmax [0:PN-1], p_ymin [0:PN-1], p_ymax [0:PN-1];
    integer p_id [0:PN-1], p_done [0:PN-1];
    reg     p_dec [0:PN-1];
    // The window of the frame on the input (a frame arms at most one set).
    reg     m_act = 1'b0;
    integer m_xmin, m_xmax, m_ymin, m_ymax, m_id = 0;
    reg     m_dec = 1'b0;
    integer m_frame = -1;            // frames started so far, minus one: the current frame's number
    integer m_frame_set = 0;         // the set the current frame armed (0: none)
    integer m_frame_k = 0;           // the edge the current frame's fval was first seen on
    integer m_pushed = 0;            // pixels of the current frame the model expects out
    integer m_counted = 0;           // the same, counted line by line from the window's geometry
    // coord_error: what it must be, and the last clock on which it may still be changing.
    reg     exp_err = 1'b0;
    integer err_settle = -1;
    reg     last_set_ok = 1'b1;      // (for messages)
    // Totals for the summary line.
    integer n_frames = 0, n_windows = 0, n_pixels = 0, n_invalid = 0, n_resets = 0;

    // Contract: a set is valid iff xmin < xmax < WIDTH and ymin < ymax < HEIGHT.
    function set_ok(input integer xmin, input integer xmax, input integer ymin, input integer ymax);
        set_ok = xmin < xmax && xmax < WIDTH && ymin < ymax && ymax < HEIGHT;
    endfunction

    // The writer's last byte was taken on edge c (coord_ready rose on it).
    task model_set_done(input integer c, input integer xmin, input integer xmax,
                        input integer ymin, input integer ymax, input d);
        begin
            n_sets = n_sets + 1;
            last_set_ok = set_ok(xmin, xmax, ymin, ymax);
            if (last_set_ok) begin
                if (p_n == PN) $fatal(1, "testbench: too many pending sets");
                p_id[p_n] = n_sets; p_done[p_n] = c; p_dec[p_n] = d;
                p_xmin[p_n] = xmin; p_xmax[p_n] = xmax; p_ymin[p_n] = ymin; p_ymax[p_n] = ymax;
                p_n = p_n + 1;
                exp_err = 1'b0;
            end else begin
                // Refused: the pending set, if any, stays as it was.
                n_invalid = n_invalid + 1;
                exp_err = 1'b1;
            end
            // coord_error answers by the edge after the last byte (checked from clock c+2).
            err_settle = c + 1;
            if (verbose)
                $display("  set %0d done at clock %0d: x %0d..%0d y %0d..%0d dec %0d, %0s", n_sets, c,
                         xmin, xmax, ymin, ymax, d, set_ok(xmin, xmax, ymin, ymax) ? "valid" : "invalid");
        end
    endtask

    // fval is first seen high on edge k: the frame arms the latest set completed on edge
    // k-ARM_MARGIN or earlier; a set completed later waits for the next frame.
    task model_frame_start(input integer k);
        integer i, w;
        begin
            m_frame = m_frame + 1;
            m_frame_k = k;
            n_frames = n_frames + 1;
            m_pushed = 0;
            m_counted = 0;
            // The latest set completed in time; the later of two such sets wins.
            w = -1;
            for (i = 0; i < p_n; i = i + 1)
                if (p_done[i] <= k - ARM_MARGIN) w = i;
            if (w >= 0) begin
                m_act = 1'b1; m_id = p_id[w]; m_dec = p_dec[w];
                m_xmin = p_xmin[w]; m_xmax = p_xmax[w]; m_ymin = p_ymin[w]; m_ymax = p_ymax[w];
                n_windows = n_windows + 1;
                // One window per set: it and the older sets are gone; later ones stay pending.
                for (i = w + 1; i < p_n; i = i + 1) begin
                    p_id[i - w - 1] = p_id[i]; p_done[i - w - 1] = p_done[i]; p_dec[i - w - 1] = p_dec[i];
                    p_xmin[i - w - 1] = p_xmin[i]; p_xmax[i - w - 1] = p_xmax[i];
                    p_ymin[i - w - 1] = p_ymin[i]; p_ymax[i - w - 1] = p_ymax[i];
                end
                p_n = p_n - w - 1;
            end else begin
                m_act = 1'b0; m_id = 0;
            end
            m_frame_set = m_id;
            if (verbose) begin
                if (m_act)
                    $display("  frame %0d (fval seen at clock %0d) arms set %0d: x %0d..%0d y %0d..%0d dec %0d",
                             m_frame, k, m_id, m_xmin, m_xmax, m_ymin, m_ymax, m_dec);
                else
                    $display("  frame %0d (fval seen at clock %0d) arms nothing", m_frame, k);
            end
        end
    endtask

    // Pixel (x, y) of the current frame must come out iff its row and its column are in the
    // armed window: on the sensor, within the bounds (inclusive), and on the 25% grid anchored
    // at (xmin, ymin) when decimated. (Split in two so the camera tests the row once a line.)
    function row_in_window(input integer y);
        row_in_window = m_act && y < HEIGHT && y >= m_ymin && y <= m_ymax
                        && (!m_dec || (y - m_ymin) % 2 == 0);
    endfunction

    function col_in_window(input integer x);
        col_in_window = x < WIDTH && x >= m_xmin && x <= m_xmax && (!m_dec || (x - m_xmin) % 2 == 0);
    endfunction

    // How many pixels of a line of `len` pixels at row y the window takes, by arithmetic:
    // a second count of the same thing, to check the pixel-by-pixel rule above.
    function integer line_count(input integer len, input integer y);
        integer last, n;
        begin
            line_count = 0;
            if (m_act && y >= m_ymin && y <= m_ymax && (!m_dec || (y - m_ymin) % 2 == 0)) begin
                last = min2(m_xmax, len - 1);
                if (last >= m_xmin) begin
                    n = last - m_xmin + 1;
                    line_count = m_dec ? (n + 1) / 2 : n;
                end
            end
        end
    endfunction

    // The expected outputs, by the edge they are due on: slot e % 16 says whether edge e
    // must strobe a pixel, its value, and {frame, y, x} for messages. The camera fills a slot
    // LATENCY edges ahead; the checker reads and empties it on edge e. (A queue would do the
    // same; the slots cost Icarus less on every pixel.)
    reg                  e_on [0:15];
    reg [PIXEL_BITS-1:0] e_v [0:15];
    reg           [47:0] e_fyx [0:15];
    integer i_init;
    initial for (i_init = 0; i_init < 16; i_init = i_init + 1) e_on[i_init] = 1'b0;

    task expect_pixel(input integer x, input integer y, input [PIXEL_BITS-1:0] v, input integer due);
        begin
            e_on[due % 16] = 1'b1; e_v[due % 16] = v; e_fyx[due % 16] = {m_frame[15:0], y[15:0], x[15:0]};
            m_pushed = m_pushed + 1;
        end
    endtask

    // What the camera drove while cyc == n, for messages: the last 16 clocks, each {a pixel
    // was on the bus, its frame, y, x} (its value is pixel_value of those).
    reg [48:0] r_fyx [0:15];

    // A synchronous reset is driven now and first seen on edge r = cyc+1: from that edge the
    // unit is in its power-on state: nothing pending or armed, coord_error low, and no pixel
    // strobed on edge r or later (the ones still in the pipeline are dropped with the rest).
    task model_reset;
        integer i;
        begin
            p_n = 0;
            m_act = 1'b0;
            exp_err = 1'b0;
            err_settle = cyc;
            for (i = 1; i <= LATENCY; i = i + 1) e_on[(cyc + i) % 16] = 1'b0;
        end
    endtask

    // ---------------------------------------------------------------------------------------
    // Checker: every clock, the unit's outputs against the model
    // ---------------------------------------------------------------------------------------
    reg wr_busy = 1'b0;              // the writer is in a handshake (see below)

    reg [8*64-1:0] scen_name = "start";   // the scenario running (set by `scenario`)
    integer scen = 0;

    task describe_window;
        begin
            $display("       in scenario %0d: %0s", scen, scen_name);
            if (m_act)
                $display("       window of this frame: set %0d, x %0d..%0d y %0d..%0d, decimate %0d",
                         m_id, m_xmin, m_xmax, m_ymin, m_ymax, m_dec);
            else
                $display("       no window is armed in frame %0d%0s", m_frame,
                         n_resets > 0 ? " (or a reset has disarmed it)" : "");
        end
    endtask

    // Say what was on the camera bus when the pixel now on pixel_out was sampled, and where a
    // wrong value came from.
    task describe_input(input [PIXEL_BITS-1:0] got);
        integer n;
        reg [48:0] r;
        begin
            r = r_fyx[(cyc - LATENCY) % 16];
            if (cyc >= LATENCY && r[48])
                $display("       the input %0d clocks earlier was pixel x=%0d y=%0d of frame %0d (value %h)",
                         LATENCY, r[15:0], r[31:16], r[47:32], pixel_value(r[47:32], r[15:0], r[31:16]));
            else
                $display("       the input %0d clocks earlier carried no pixel", LATENCY);
            for (n = 1; n < 15 && n <= cyc; n = n + 1) begin
                r = r_fyx[(cyc - n) % 16];
                if (r[48] && pixel_value(r[47:32], r[15:0], r[31:16]) === got)
                    $display("       value %h is pixel x=%0d y=%0d of frame %0d, on the input at clock %0d",
                             got, r[15:0], r[31:16], r[47:32], cyc - n);
            end
        end
    endtask

    always @(negedge clock) begin : check_outputs
        integer e;
        e = cyc % 16;
        if (e_on[e]) begin
            if (pixel_strobe !== 1'b1) begin
                $display("FAIL window_unit %0dx%0d %0d seed %0d: frame %0d clock %0d: expected pixel x=%0d y=%0d value %h, got no pixel_strobe (%b)",
                         WIDTH, HEIGHT, PIXEL_BITS, SEED, e_fyx[e][47:32], cyc, e_fyx[e][15:0],
                         e_fyx[e][31:16], e_v[e], pixel_strobe);
                describe_window;
                $fatal(1, "window_unit: missing pixel");
            end
            if (pixel_out !== e_v[e]) begin
                $display("FAIL window_unit %0dx%0d %0d seed %0d: frame %0d clock %0d: expected pixel x=%0d y=%0d value %h, got value %h",
                         WIDTH, HEIGHT, PIXEL_BITS, SEED, e_fyx[e][47:32], cyc, e_fyx[e][15:0],
                         e_fyx[e][31:16], e_v[e], pixel_out);
                describe_input(pixel_out);
                describe_window;
                $fatal(1, "window_unit: wrong pixel");
            end
            e_on[e] = 1'b0;
            n_pixels = n_pixels + 1;
        end else if (pixel_strobe !== 1'b0) begin
            $display("FAIL window_unit %0dx%0d %0d seed %0d: frame %0d clock %0d: expected no pixel, got pixel_strobe (%b) with value %h",
                     WIDTH, HEIGHT, PIXEL_BITS, SEED, m_frame, cyc, pixel_strobe, pixel_out);
            describe_input(pixel_out);
            describe_window;
            $fatal(1, "window_unit: unexpected pixel");
        end
        if (cyc > err_settle && coord_error !== exp_err) begin
            $display("FAIL window_unit %0dx%0d %0d seed %0d: clock %0d: coord_error is %b, expected %b (%0d sets written, the last %0s; %0d resets)",
                     WIDTH, HEIGHT, PIXEL_BITS, SEED, cyc, coord_error, exp_err, n_sets,
                     last_set_ok ? "valid" : "invalid", n_resets);
            $display("       in scenario %0d: %0s", scen, scen_name);
            $fatal(1, "window_unit: wrong coord_error");
        end
        if (!wr_busy && coord_ready !== 1'b0) begin
            $display("FAIL window_unit %0dx%0d %0d seed %0d: clock %0d: coord_ready is %b with no byte offered",
                     WIDTH, HEIGHT, PIXEL_BITS, SEED, cyc, coord_ready);
            $display("       in scenario %0d: %0s", scen, scen_name);
            $fatal(1, "window_unit: spurious coord_ready");
        end
    end

    // ---------------------------------------------------------------------------------------
    // Camera
    // ---------------------------------------------------------------------------------------
    // The geometry of the next frame, set by the geom_* tasks: g_lines lines; rows
    // g_band_lo..g_band_hi have g_band_len pixels, the others g_len (a band of full-length
    // lines around the window keeps large sensors cheap to simulate; "one lval pulse is one
    // line however many clocks", so lines of different lengths are a legal raster).
    integer g_lines, g_len, g_band_lo, g_band_hi, g_band_len;
    // pixel_valid: -1 tied high (also in blanking); 0 high through each line, random in
    // blanking; 1..99 that percentage of the clocks inside a line carry no pixel.
    integer g_gaps;
    integer g_vb_pulses = 2;         // most lval pulses while fval is low after the frame
    integer g_cut = -1;              // pixels of the last line after fval falls (-1: random), next frame only

    // One clock of camera output that is not a pixel of the frame (blanking: lval low, or
    // lval high while fval is low). Junk on the pixel bus; pixel_valid random, since it
    // means nothing here, unless the camera ties it high. (One $random a clock: Icarus spends
    // as much on a system call as on the unit's whole clock.)
    task cam_blank(input f, input l);
        reg [31:0] r;
        begin
            r = $random(seed);
            fval = f; lval = l; pixel_valid = g_gaps < 0 ? 1'b1 : r[31]; pixel = r;
            r_fyx[cyc % 16] = 49'd0;
            @(negedge clock);
        end
    endtask

    // One clock inside a line with no pixel (a pixel_valid gap).
    task cam_gap;
        begin
            fval = 1'b1; lval = 1'b1; pixel_valid = 1'b0; pixel = ~pixel;
            r_fyx[cyc % 16] = 49'd0;
            @(negedge clock);
        end
    endtask

    // True when the next clock inside a line should be a gap.
    function gap_now(input integer dummy);
        gap_now = g_gaps > 0 && ({$random(seed)} % 100) < g_gaps;
    endfunction

    // One clock of a line cut short by fval's fall: lval and pixel_valid high and what would
    // be pixel (x, y) on the bus, but fval low, so it is no pixel.
    task cam_after_fval(input integer x, input integer y);
        begin
            fval = 1'b0; lval = 1'b1; pixel_valid = 1'b1; pixel = pixel_value(m_frame, x, y);
            r_fyx[cyc % 16] = 49'd0;
            @(negedge clock);
        end
    endtask

    // One clock carrying pixel (x, y) of the current frame; row_in: the row is in the window.
    // The model decides here whether the pixel must come out, and when.
    task cam_pixel(input integer x, input integer y, input row_in);
        reg [PIXEL_BITS-1:0] v;
        begin
            v = pixel_value(m_frame, x, y);
            fval = 1'b1; lval = 1'b1; pixel_valid = 1'b1; pixel = v;
            r_fyx[cyc % 16] = {1'b1, m_frame[15:0], y[15:0], x[15:0]};
            if (row_in && m_act)   // (m_act again: a reset may come mid-line)
                if (col_in_window(x)) expect_pixel(x, y, v, cyc + LATENCY);
            @(negedge clock);
        end
    endtask

    // One frame: fval rises now, lines, fval falls, then vertical blanking with lval pulses.
    // Returns at a falling edge with fval low.
    task camera_frame;
        integer y, x, len, cut;
        reg row_in, gap;
        begin
            // fval driven now is first seen on the next edge. (A hair after the falling edge,
            // so that a set the writer sees completed on this same falling edge is counted.)
            #1;
            model_frame_start(cyc + 1);
            // Sometimes fval falls while the last line is still being sent: its last `cut`
            // pixels come with fval low, so they are no pixels of the frame.
            cut = g_cut >= 0 ? g_cut : chance(15) ? rnd(1, 5) : 0;
            g_cut = -1;
            // fval high before the first line.
            repeat (rnd(FP_MIN, HB_MAX)) cam_blank(1, 0);
            for (y = 0; y < g_lines; y = y + 1) begin
                len = (y >= g_band_lo && y <= g_band_hi) ? g_band_len : g_len;
                if (y == g_lines - 1) begin
                    cut = min2(cut, len);
                    len = len - cut;
                end
                row_in = row_in_window(y);
                m_counted = m_counted + line_count(len, y);
                x = 0;
                while (x < len) begin
                    gap = 1'b0;
                    if (g_gaps > 0) gap = gap_now(0);   // (Icarus calls both sides of an &&)
                    if (gap) begin
                        cam_gap;
                    end else begin
                        cam_pixel(x, y, row_in);
                        x = x + 1;
                    end
                end
                // lval may outlast the line's last pixel.
                if (g_gaps > 0) repeat (rnd(0, 2)) cam_gap;
                if (y < g_lines - 1) repeat (rnd(HB_MIN, HB_MAX)) cam_blank(1, 0);
            end
            if (cut > 0) begin
                repeat (cut) begin
                    cam_after_fval(x, y - 1);
                    x = x + 1;
                end
                cam_blank(0, 0);
            end else begin
                repeat (rnd(0, BP_MAX)) cam_blank(1, 0);
            end
            // Vertical blanking: fval low; lval may still pulse (as the CA-D1's does).
            repeat (rnd(0, g_vb_pulses)) begin
                repeat (rnd(HB_MIN, HB_MAX)) cam_blank(0, 0);
                repeat (rnd(1, 16)) cam_blank(0, 1);
            end
            repeat (rnd(1, 4)) cam_blank(0, 0);
            // The model against itself: pixels it pushed one by one = the per-line count.
            if (m_act && m_pushed != m_counted)
                $fatal(1, "testbench: model pushed %0d pixels in frame %0d, geometry says %0d",
                       m_pushed, m_frame, m_counted);
        end
    endtask

    function integer rand_gaps(input integer dummy);
        integer r;
        begin
            r = rnd(0, 99);
            rand_gaps = r < 30 ? -1 : r < 50 ? 0 : rnd(5, 40);
        end
    endfunction

    task geom(input integer lines, input integer len, input integer band_lo, input integer band_hi,
              input integer band_len, input integer gaps);
        begin
            g_lines = lines; g_len = len; g_band_lo = band_lo; g_band_hi = band_hi;
            g_band_len = band_len; g_gaps = gaps;
        end
    endtask

    // The whole sensor, every line WIDTH pixels.
    task geom_full(input integer gaps);
        geom(HEIGHT, WIDTH, 0, -1, 0, gaps);
    endtask

    // A short frame (few short lines), for frames that must deliver nothing.
    task geom_small;
        geom(rnd(2, min2(HEIGHT, 24)), rnd(1, min2(WIDTH, 40)), 0, -1, 0, rand_gaps(0));
    endtask

    // A frame that covers the window x xmin..xmax, y ymin..ymax (and usually the whole
    // sensor): small sensors whole, sometimes with longer lines and more lines; large ones
    // with full-length lines only in a band of rows around the window.
    task geom_around(input integer xmin, input integer xmax, input integer ymin, input integer ymax);
        integer lines, extra_x, lo, hi, n;
        begin
            // Usually exactly HEIGHT lines, sometimes more; sometimes the frame stops just after
            // the window (usually, on a large sensor, where the rows after it cost time).
            n = rnd(0, 99);
            lines = n < 20 ? HEIGHT + rnd(1, 8) : n < (BIG ? 70 : 35) ? ymax + 1 + rnd(0, 2) : HEIGHT;
            extra_x = chance(25) ? rnd(1, 40) : 0;
            lo = ymin - rnd(0, 2);
            hi = ymax + rnd(0, 2);
            if (!BIG)
                geom(lines, WIDTH + extra_x, 0, -1, 0, rand_gaps(0));
            else
                // Band lines run to the sensor's edge when that stays cheap, else just past xmax.
                geom(lines, rnd(1, 8), lo, hi,
                     (hi - lo + 1) * WIDTH <= 2 * DENSE_MAX && chance(50) ? WIDTH + extra_x
                                                                          : xmax + 1 + rnd(0, 3),
                     rand_gaps(0));
        end
    endtask

    // Make the next frame long enough for a whole set to be written while it is on.
    task geom_long_enough;
        begin
            g_len = max2(g_len, min2(WIDTH, 24));
            g_lines = max2(g_lines, HEIGHT);
        end
    endtask

    // ---------------------------------------------------------------------------------------
    // Writer: the processor's side of the coordinate port
    // ---------------------------------------------------------------------------------------
    reg        wr_go = 1'b0;        // a set is waiting to be written
    reg        wr_taken = 1'b0;     // the set's last byte was taken (coord_ready rose)
    reg        wr_last_offered = 1'b0;  // the set's last byte is being offered (strobe high)
    integer    wr_lat = 2;          // clocks from strobe to coord_ready, for the last byte taken
    reg        wr_abort = 1'b0;     // a reset: drop the strobe and give up the set
    integer    wr_nbytes_taken = 0; // bytes of the current set taken so far
    integer    wr_xmin, wr_xmax, wr_ymin, wr_ymax;
    reg        wr_dec;
    integer    wr_done = -1;        // edge the last set's last byte was taken on

    // Byte i of the set: xmin, xmax, ymin, ymax, each high byte first when WIDE.
    function [7:0] set_byte(input integer i);
        integer c;
        begin
            c = WIDE ? i / 2 : i;
            c = c == 0 ? wr_xmin : c == 1 ? wr_xmax : c == 2 ? wr_ymin : wr_ymax;
            set_byte = (WIDE && i % 2 == 0) ? c[15:8] : c[7:0];
        end
    endfunction

    // The writer process: each set as NBYTES four-phase handshakes. The strobe is held a
    // random 0..2 clocks past coord_ready, and bytes are 0..3 clocks apart, as a processor
    // polling the port might. decimate is random on all bytes but the last, whose value counts.
    initial begin : writer
        integer i, n;
        forever begin
            wait (wr_go);
            wr_busy = 1'b1; wr_go = 1'b0; wr_taken = 1'b0; wr_last_offered = 1'b0; wr_nbytes_taken = 0;
            for (i = 0; i < NBYTES && !wr_abort; i = i + 1) begin
                if (coord_ready !== 1'b0) begin
                    $display("FAIL window_unit %0dx%0d %0d seed %0d: clock %0d: coord_ready is still high before byte %0d of set %0d",
                             WIDTH, HEIGHT, PIXEL_BITS, SEED, cyc, i, n_sets + 1);
                    $display("       in scenario %0d: %0s", scen, scen_name);
                    $fatal(1, "window_unit: handshake");
                end
                coord_data = set_byte(i);
                decimate = i == NBYTES - 1 ? wr_dec : rnd(0, 1);
                coord_strobe = 1'b1;
                if (i == NBYTES - 1) wr_last_offered = 1'b1;
                n = 0;
                while (coord_ready !== 1'b1 && !wr_abort) begin
                    @(negedge clock);
                    n = n + 1;
                    if (coord_ready !== 1'b1 && !wr_abort && n >= 4) begin
                        $display("FAIL window_unit %0dx%0d %0d seed %0d: clock %0d: coord_ready did not rise within 4 clocks of coord_strobe (byte %0d of set %0d)",
                                 WIDTH, HEIGHT, PIXEL_BITS, SEED, cyc, i, n_sets + 1);
                        $display("       in scenario %0d: %0s", scen, scen_name);
                        $fatal(1, "window_unit: handshake");
                    end
                end
                if (!wr_abort) begin
                    wr_nbytes_taken = i + 1;
                    wr_lat = n;
                    if (i == NBYTES - 1) begin
                        wr_done = cyc;
                        model_set_done(cyc, wr_xmin, wr_xmax, wr_ymin, wr_ymax, wr_dec);
                        wr_taken = 1'b1;
                    end
                    // Hold the strobe a little; ready must stay high while it is.
                    repeat (rnd(0, 2)) begin
                        @(negedge clock);
                        if (!wr_abort && coord_ready !== 1'b1) begin
                            $display("FAIL window_unit %0dx%0d %0d seed %0d: clock %0d: coord_ready fell while coord_strobe was still high (byte %0d of set %0d)",
                                     WIDTH, HEIGHT, PIXEL_BITS, SEED, cyc, i, n_sets + (i == NBYTES - 1 ? 0 : 1));
                            $display("       in scenario %0d: %0s", scen, scen_name);
                            $fatal(1, "window_unit: handshake");
                        end
                    end
                end
                coord_strobe = 1'b0;
                coord_data = $random(seed);
                decimate = rnd(0, 1);
                n = 0;
                while (coord_ready !== 1'b0 && !wr_abort) begin
                    @(negedge clock);
                    n = n + 1;
                    if (coord_ready !== 1'b0 && !wr_abort && n >= 4) begin
                        $display("FAIL window_unit %0dx%0d %0d seed %0d: clock %0d: coord_ready did not fall within 4 clocks of the strobe's end (byte %0d)",
                                 WIDTH, HEIGHT, PIXEL_BITS, SEED, cyc, i);
                        $display("       in scenario %0d: %0s", scen, scen_name);
                        $fatal(1, "window_unit: handshake");
                    end
                end
                if (!wr_abort) repeat (rnd(0, 3)) @(negedge clock);
            end
            // After an abort the reset clears coord_ready; the writer is idle once it has.
            coord_strobe = 1'b0;
            while (coord_ready !== 1'b0) @(negedge clock);
            wr_abort = 1'b0;
            wr_busy = 1'b0;
        end
    end

    // Hand a set to the writer and return at once (it is written in the background).
    task start_set(input integer xmin, input integer xmax, input integer ymin, input integer ymax,
                   input d);
        begin
            wait (!wr_busy && !wr_go);
            wr_xmin = xmin; wr_xmax = xmax; wr_ymin = ymin; wr_ymax = ymax; wr_dec = d;
            wr_taken = 1'b0; wr_last_offered = 1'b0;
            wr_go = 1'b1;
            wait (wr_busy);
        end
    endtask

    // Write a set and wait until the handshake of its last byte is over. Returns its number.
    task write_set(input integer xmin, input integer xmax, input integer ymin, input integer ymax,
                   input d, output integer id);
        begin
            start_set(xmin, xmax, ymin, ymax, d);
            wait (!wr_busy);
            @(negedge clock);
            id = n_sets;
        end
    endtask

    // ---------------------------------------------------------------------------------------
    // Reset
    // ---------------------------------------------------------------------------------------
    // Hold reset for n clocks; the writer gives up a set in progress (the processor is reset
    // with the unit) and drops its strobe on the same clock.
    task pulse_reset(input integer n);
        begin
            n_resets = n_resets + 1;
            if (verbose) $display("  reset at clock %0d for %0d clocks", cyc + 1, n);
            model_reset;
            if (wr_busy) wr_abort = 1'b1;
            coord_strobe = 1'b0;
            reset = 1'b1;
            idle(n);
            reset = 1'b0;
        end
    endtask

    // ---------------------------------------------------------------------------------------
    // Scenario helpers
    // ---------------------------------------------------------------------------------------
    integer id, id_a, id_b;

    task scenario(input [8*64-1:0] name);
        begin
            scen = scen + 1;
            scen_name = name;
            if (verbose) $display("scenario %0d at clock %0d: %0s", scen, cyc, name);
        end
    endtask

    // The scenario's intent against the model: a testbench error, not the unit's.
    task expect_armed(input integer want_set);
        begin
            if (m_frame_set != want_set)
                $fatal(1, "testbench: scenario %0d expected frame %0d to arm set %0d, the model armed %0d",
                       scen, m_frame, want_set, m_frame_set);
        end
    endtask

    // Write a valid set, send a frame around it, and expect that frame to deliver it.
    task window_frame(input integer xmin, input integer xmax, input integer ymin, input integer ymax,
                      input d);
        begin
            write_set(xmin, xmax, ymin, ymax, d, id);
            geom_around(xmin, xmax, ymin, ymax);
            camera_frame;
            expect_armed(id);
        end
    endtask

    // The set handed to the writer has its last byte taken `delta` clocks before the edge on
    // which the next frame's fval is first seen: send that frame (geometry already set). The
    // last byte is taken as long after its strobe as the byte before it was (the unit's
    // latency is fixed); the timing is checked afterwards.
    task frame_after_set(input integer delta);
        begin
            wait (wr_last_offered);        // the last byte's strobe rises on this falling edge
            idle(wr_lat + delta - 1);      // fval driven on the next falling edge is seen delta after
            camera_frame;
            if (m_frame_k - wr_done != delta)
                $fatal(1, "testbench: scenario %0d wanted the set %0d clocks before fval, got %0d",
                       scen, delta, m_frame_k - wr_done);
        end
    endtask

    // A frame that must deliver nothing (no set pending).
    task empty_frame;
        begin
            geom_small;
            camera_frame;
            expect_armed(0);
        end
    endtask

    // A random valid window: mostly small, some anywhere up to the whole sensor (rows limited
    // to BAND_ROWS on large sensors), some against an edge. `tiny`: at most 8x8.
    integer rw_xmin, rw_xmax, rw_ymin, rw_ymax;
    task rand_window(input tiny);
        integer w, h, r;
        begin
            r = tiny ? 50 : rnd(0, 99);
            w = r < 25 ? 2 : r < 65 ? rnd(2, tiny ? 8 : min2(WIDTH, 17)) : rnd(2, WIDTH);
            r = tiny ? 50 : rnd(0, 99);
            h = r < 25 ? 2 : r < 65 ? rnd(2, tiny ? 8 : min2(HEIGHT, 17))
                                    : rnd(2, BIG ? min2(HEIGHT, BAND_ROWS) : HEIGHT);
            r = rnd(0, 99);
            rw_xmin = r < 15 ? 0 : r < 30 ? WIDTH - w : rnd(0, WIDTH - w);
            r = rnd(0, 99);
            rw_ymin = r < 15 ? 0 : r < 30 ? HEIGHT - h : rnd(0, HEIGHT - h);
            rw_xmax = rw_xmin + w - 1;
            rw_ymax = rw_ymin + h - 1;
        end
    endtask

    // An invalid set of the given kind; returns 0 if this size cannot express it.
    task invalid_set(input integer kind, output ok);
        integer hi;
        begin
            ok = 1'b1;
            rw_xmin = rnd(0, WIDTH - 2); rw_xmax = rnd(rw_xmin + 1, WIDTH - 1);
            rw_ymin = rnd(0, HEIGHT - 2); rw_ymax = rnd(rw_ymin + 1, HEIGHT - 1);
            case (kind)
                0: rw_xmax = rw_xmin;                                   // xmin = xmax
                1: begin rw_xmin = rnd(1, WIDTH - 1); rw_xmax = rnd(0, rw_xmin - 1); end   // xmin > xmax
                2: if (WIDTH <= CMAX) rw_xmax = WIDTH; else ok = 1'b0;          // xmax = WIDTH
                3: if (HEIGHT <= CMAX) rw_ymax = HEIGHT; else ok = 1'b0;        // ymax = HEIGHT
                4: rw_ymax = rw_ymin;                                   // ymin = ymax
                5: begin rw_ymin = rnd(1, HEIGHT - 1); rw_ymax = rnd(0, rw_ymin - 1); end
                6: if (WIDE) begin                                      // xmax's high byte beyond range
                       hi = rnd((WIDTH + 255) / 256, 255);
                       rw_xmax = hi * 256 + rnd(0, 255);
                       if (rw_xmax < WIDTH) rw_xmax = WIDTH;
                   end else ok = 1'b0;
                7: if (WIDE) rw_ymin = rnd(128, 255) * 256 + rnd(0, 255);   // ymin's high byte: ymin > ymax
                   else ok = 1'b0;
                8: if (WIDE) begin                                      // ymax's high byte beyond range
                       hi = rnd((HEIGHT + 255) / 256, 255);
                       rw_ymax = hi * 256 + rnd(0, 255);
                       if (rw_ymax < HEIGHT) rw_ymax = HEIGHT;
                   end else ok = 1'b0;
                9: if (WIDE) begin  // a column whose low bits alias a valid one: 2^k + x, 2^k >= WIDTH
                       hi = 1;
                       while (hi < WIDTH) hi = hi * 2;
                       rw_xmax = hi + rw_xmax;
                       if (rw_xmax > CMAX) ok = 1'b0;
                   end else ok = 1'b0;
                10: if (WIDTH < CMAX) rw_xmax = rnd(WIDTH + 1, min2(CMAX, WIDTH + 300)); else ok = 1'b0;
                11: if (HEIGHT < CMAX) rw_ymax = rnd(HEIGHT + 1, min2(CMAX, HEIGHT + 300)); else ok = 1'b0;
                default: ok = 1'b0;
            endcase
        end
    endtask

    // ---------------------------------------------------------------------------------------
    // Scenarios
    // ---------------------------------------------------------------------------------------
    integer i, j, k, a, b, n, p2;
    reg ok;

    initial begin : scenarios
        if ($test$plusargs("verbose")) verbose = 1'b1;
        if (WIDTH < 16 || WIDTH > 4096 || HEIGHT < 16 || HEIGHT > 4096 || PIXEL_BITS < 8 || PIXEL_BITS > 16)
            $fatal(1, "testbench: WIDTH, HEIGHT must be 16..4096 and PIXEL_BITS 8..16 (got %0dx%0d %0d)",
                   WIDTH, HEIGHT, PIXEL_BITS);
        // The next power of two from the larger dimension: a line or frame twice that long
        // overruns any counter just wide enough for the coordinates.
        p2 = 1;
        while (p2 < max2(WIDTH, HEIGHT)) p2 = p2 * 2;
        idle(4);

        // Power-on: no set, no window; coord_error low (the checker checks it every clock).
        scenario("power-on frame delivers nothing");
        empty_frame;

        // The whole sensor, in frames sent whole (the first with pixel_valid tied high).
        for (i = 0; i < FULL_FRAMES; i = i + 1) begin
            scenario("full-frame window in a full frame");
            write_set(0, WIDTH - 1, 0, HEIGHT - 1, 1'b0, id);
            geom_full(i == 0 ? -1 : rand_gaps(0));
            camera_frame;
            expect_armed(id);
        end

        // One window per set: the next frame delivers nothing.
        scenario("no new set: nothing");
        empty_frame;
        geom_full(-1);
        g_lines = min2(HEIGHT, 3);   // whole lines, few of them
        camera_frame;
        expect_armed(0);

        // Windows against each edge and corner, and 2-pixel-wide/high ones.
        scenario("edge and corner windows");
        a = rnd(1, min2(WIDTH - 1, 9)); b = rnd(1, min2(HEIGHT - 1, 9));
        window_frame(0, a, 0, b, 1'b0);                                  // x = 0, y = 0
        window_frame(WIDTH - 1 - a, WIDTH - 1, 0, b, 1'b0);              // x = WIDTH-1
        window_frame(0, a, HEIGHT - 1 - b, HEIGHT - 1, 1'b0);            // y = HEIGHT-1
        window_frame(WIDTH - 1 - a, WIDTH - 1, HEIGHT - 1 - b, HEIGHT - 1, 1'b0);
        window_frame(0, WIDTH - 1, b, b + 1, 1'b0);                      // full width, 2 rows
        window_frame(a, a + 1, 0, HEIGHT - 1, 1'b0);                     // full height, 2 columns (band = all rows)
        scenario("2x2 windows");
        window_frame(0, 1, 0, 1, 1'b0);
        window_frame(WIDTH - 2, WIDTH - 1, HEIGHT - 2, HEIGHT - 1, 1'b0);
        window_frame(WIDTH - 2, WIDTH - 1, 0, 1, 1'b0);
        window_frame(0, 1, HEIGHT - 2, HEIGHT - 1, 1'b0);
        for (i = 0; i < 3; i = i + 1) begin
            a = rnd(0, WIDTH - 2); b = rnd(0, HEIGHT - 2);
            window_frame(a, a + 1, b, b + 1, 1'b0);
        end

        // Decimation: odd and even origins and sizes, against the edges.
        scenario("decimated windows");
        window_frame(0, 1, 0, 1, 1'b1);                                  // one pixel out of 2x2
        window_frame(1, 3, 1, 3, 1'b1);                                  // 3x3 from odd corner: 2x2
        window_frame(WIDTH - 3, WIDTH - 1, HEIGHT - 3, HEIGHT - 1, 1'b1);
        window_frame(WIDTH - 4, WIDTH - 1, HEIGHT - 5, HEIGHT - 1, 1'b1);
        for (i = 0; i < 4; i = i + 1) begin
            rand_window(0);
            window_frame(rw_xmin, rw_xmax, rw_ymin, rw_ymax, 1'b1);
        end
        if (!BIG) window_frame(0, WIDTH - 1, 0, HEIGHT - 1, 1'b1);

        // Invalid sets are refused: coord_error rises and the pending set stays.
        scenario("invalid sets refused");
        rand_window(0);
        write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50), id_a);
        a = rw_xmin; b = rw_xmax; j = rw_ymin; k = rw_ymax;
        for (i = 0; i < 12; i = i + 1) begin
            invalid_set(i, ok);
            if (ok) write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50), id);
        end
        geom_around(a, b, j, k);
        camera_frame;
        expect_armed(id_a);
        // Still high with nothing pending; an invalid set with nothing pending arms nothing.
        invalid_set(rnd(0, 5), ok);
        if (ok) write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, 1'b0, id);
        empty_frame;
        // A valid set clears it.
        rand_window(0);
        window_frame(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50));

        // Of two sets completed before a frame, the later wins; the earlier is never delivered.
        scenario("two sets before a frame: the later wins");
        rand_window(0);
        write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50), id_a);
        rand_window(0);
        write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50), id_b);
        geom_around(rw_xmin, rw_xmax, rw_ymin, rw_ymax);
        camera_frame;
        expect_armed(id_b);
        empty_frame;

        // A set written during a frame arms the next one, and leaves the current window alone.
        scenario("set written during a frame arms the next");
        rand_window(0);
        write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50), id_a);
        geom_around(rw_xmin, rw_xmax, rw_ymin, rw_ymax);
        geom_long_enough;
        rand_window(0);
        fork
            camera_frame;
            begin
                idle(rnd(HB_MAX + 2, 4 * HB_MAX));
                start_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50));
                wait (wr_taken);
                if (fval !== 1'b1) $fatal(1, "testbench: the mid-frame set completed outside the frame");
                id_b = n_sets;
                wait (!wr_busy);
            end
        join
        expect_armed(id_a);
        geom_around(rw_xmin, rw_xmax, rw_ymin, rw_ymax);
        camera_frame;
        expect_armed(id_b);
        empty_frame;

        // The arming margin: a set whose last byte is taken on edge c arms a frame whose fval
        // is first seen on edge c+ARM_MARGIN, but not one seen on edge c+ARM_MARGIN-1 (that
        // set waits a frame).
        scenario("set completed ARM_MARGIN clocks before fval arms it");
        rand_window(0);
        start_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50));
        id_a = n_sets + 1;                        // (sets are numbered as they complete)
        geom_around(rw_xmin, rw_xmax, rw_ymin, rw_ymax);
        frame_after_set(ARM_MARGIN);
        expect_armed(id_a);
        scenario("set completed ARM_MARGIN-1 clocks before fval waits a frame");
        rand_window(0);
        start_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50));
        id_b = n_sets + 1;
        geom_small;
        frame_after_set(ARM_MARGIN - 1);
        expect_armed(0);
        geom_around(rw_xmin, rw_xmax, rw_ymin, rw_ymax);
        camera_frame;
        expect_armed(id_b);
        // A set pending, then a second completed ARM_MARGIN clocks before fval: the second wins.
        scenario("second set ARM_MARGIN clocks before fval wins");
        rand_window(0);
        write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50), id_a);
        rand_window(0);
        start_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50));
        id_b = n_sets + 1;
        geom_around(rw_xmin, rw_xmax, rw_ymin, rw_ymax);
        frame_after_set(ARM_MARGIN);
        expect_armed(id_b);
        empty_frame;
        // A set pending, then a second completed ARM_MARGIN-1 clocks before fval: the pending
        // one was in time, so it arms this frame; the second arms the next. Both windows are
        // in both frames, so whichever the unit arms shows.
        scenario("second set ARM_MARGIN-1 clocks before fval waits");
        rand_window(0);
        write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50), id_a);
        a = rw_xmin; b = rw_xmax; j = rw_ymin; k = rw_ymax;
        rand_window(0);
        start_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50));
        id_b = id_a + 1;
        geom_around(min2(a, rw_xmin), max2(b, rw_xmax), min2(j, rw_ymin), max2(k, rw_ymax));
        frame_after_set(ARM_MARGIN - 1);
        expect_armed(id_a);
        geom_around(min2(a, rw_xmin), max2(b, rw_xmax), min2(j, rw_ymin), max2(k, rw_ymax));
        camera_frame;
        expect_armed(id_b);
        empty_frame;

        // Reset while a window is being delivered: the rest is not delivered, nothing after
        // until a new set, coord_error low (made high first by an invalid set).
        scenario("reset in the middle of a window");
        // At least 6x6 (9 pixels decimated): the reset comes after 1..4 pixels and 0..3 clocks.
        a = rnd(0, WIDTH - 8); b = rnd(0, HEIGHT - 8);
        j = a + rnd(5, min2(WIDTH - 1 - a, 40));
        k = b + rnd(5, 7);
        write_set(a, j, b, k, chance(50), id_a);
        geom_around(a, j, b, k);
        write_set(5, 4, 0, 1, 1'b0, id);          // invalid: coord_error high, set a still pending
        n = rnd(1, 4);                            // pixels to let out before the reset
        m_pushed = 0;                             // (camera_frame zeroes it too, but may start second)
        fork
            camera_frame;
            begin
                wait (m_pushed >= n);
                idle(rnd(0, 3));
                pulse_reset(rnd(1, 3));
            end
        join
        expect_armed(id_a);
        empty_frame;
        rand_window(0);
        window_frame(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50));

        // Reset between frames with a set pending: the set is gone.
        scenario("reset with a set pending");
        rand_window(0);
        write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50), id);
        pulse_reset(rnd(1, 3));
        geom_around(rw_xmin, rw_xmax, rw_ymin, rw_ymax);
        camera_frame;
        expect_armed(0);

        // Reset in the middle of writing a set: the bytes written are dropped, and the next
        // set is read from its first byte.
        for (i = 1; i < NBYTES; i = i + 1) begin
            scenario("reset in the middle of a coordinate write");
            rand_window(1);
            write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50), id);   // pending, lost to the reset
            rand_window(1);
            start_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50));
            wait (wr_nbytes_taken >= i);
            idle(rnd(0, 2));                      // strobe high, ready high, or between bytes
            if (wr_taken) $fatal(1, "testbench: the set completed before the reset");
            pulse_reset(rnd(1, 3));
            wait (!wr_busy);
            empty_frame;
            rand_window(1);
            window_frame(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50));
        end

        // fval falls while the window's last line is still being sent: the pixels after its
        // fall are no pixels and must not come out.
        scenario("fval falls before the last line ends");
        a = rnd(0, WIDTH - 6); b = rnd(0, HEIGHT - 3);
        j = rnd(a + 5, WIDTH - 1); k = rnd(b + 1, HEIGHT - 1);
        write_set(a, j, b, k, 1'b0, id);
        geom(k + 1, rnd(1, 8), b, k, j + 1, rand_gaps(0));   // the window's last row is the frame's last line
        g_cut = rnd(1, 5);
        camera_frame;
        expect_armed(id);

        // Lines and frames beyond the sensor (and beyond twice the next power of two, so a
        // counter that wrapped would come round to the window again): never delivered.
        scenario("lines longer than WIDTH");
        g_vb_pulses = 2;
        a = rnd(1, min2(WIDTH - 1, 7)); b = rnd(1, min2(HEIGHT - 1, 3));
        write_set(0, a, 0, b, 1'b0, id);
        geom(b + 1 + rnd(0, 2), 2 * p2 + rnd(1, 17), 0, -1, 0, chance(50) ? -1 : rnd(0, 10));
        camera_frame;
        expect_armed(id);
        write_set(WIDTH - 1 - a, WIDTH - 1, 0, b, chance(50), id);
        geom(b + 1 + rnd(0, 2), 2 * p2 + rnd(1, 17), 0, -1, 0, chance(50) ? -1 : rnd(0, 10));
        camera_frame;
        expect_armed(id);
        scenario("frames longer than HEIGHT");
        write_set(0, a, HEIGHT - 1 - b, HEIGHT - 1, chance(50), id);
        geom(2 * p2 + rnd(1, 17), a + 1 + rnd(0, 3), 0, -1, 0, -1);
        camera_frame;
        expect_armed(id);

        // Random: windows, decimation, invalid sets, two sets, sets written during the frame
        // before, frames with no set; the model decides what each frame must deliver.
        for (i = 0; i < RANDOM_FRAMES; i = i + 1) begin
            scenario("random");
            n = rnd(0, 99);
            if (n < 10) begin
                invalid_set(rnd(0, 11), ok);
                if (ok) write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(50), id);
            end
            if (n >= 10 && n < 85) begin
                rand_window(0);
                write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(40), id);
            end
            if (n >= 75 && n < 85) begin
                rand_window(0);
                write_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(40), id);
            end
            // A frame around the window it will arm, if any (the latest pending set).
            if (p_n > 0) geom_around(p_xmin[p_n - 1], p_xmax[p_n - 1], p_ymin[p_n - 1], p_ymax[p_n - 1]);
            else geom_small;
            if (chance(25)) begin
                // Also write a set during this frame: it arms the next.
                rand_window(0);
                geom_long_enough;
                fork
                    camera_frame;
                    begin
                        idle(rnd(HB_MAX + 2, 4 * HB_MAX));
                        start_set(rw_xmin, rw_xmax, rw_ymin, rw_ymax, chance(40));
                        wait (!wr_busy);
                    end
                join
            end else begin
                camera_frame;
            end
        end

        // Let the pipeline drain; every expected pixel must have been checked by now.
        idle(LATENCY + 4);
        for (i = 0; i < 16; i = i + 1)
            if (e_on[i]) $fatal(1, "testbench: an expected pixel was never checked");
        if (verbose) $display("%0d clocks", cyc);
        $display("PASS window_unit %0dx%0d %0d: %0d frames, %0d windows, %0d pixels checked, %0d invalid sets refused",
                 WIDTH, HEIGHT, PIXEL_BITS, n_frames, n_windows, n_pixels, n_invalid);
        $finish;
    end
endmodule

`default_nettype wire
