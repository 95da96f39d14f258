// Formal harness for window_unit (hdl/verilog/window_unit.v): the contract as properties.
// Read with `read_verilog -formal -sv`; scripts/formal.sh runs every proof (docs/formal.md).
//
// The harness drives the unit from free inputs, constrains them only as the contract lets a
// camera and a processor behave (the assumptions below), keeps its own shadow state computed
// from those inputs (the camera's column and row, the set as the processor wrote it, which
// frame it arms), and asserts the unit's ports against that shadow.
//
// Properties (assert labels; scripts/formal.sh reports them by these names):
//   P_inside     a pixel is strobed only inside the armed window (and on its 25% grid)
//   P_data       a strobed pixel_out is the camera pixel of that position, two clocks later
//   P_complete   every pixel of an armed window is strobed (with P_inside: exactly the window)
//   P_bounds     no pixel beyond column WIDTH-1 or line HEIGHT-1 is ever strobed
//   P_noset      no strobe in a frame that no valid set armed
//   P_invalid    a frame after an invalid set (no valid one pending) strobes nothing
//   P_invalid_error  coord_error is high exactly from a refused set to the next valid one
//   P_hs_*       the handshake: coord_ready rises only for an offered byte, falls only once
//                the strobe is low, and answers each strobe edge within 4 clocks
//   P_armed      armed is high exactly while a valid set waits for a frame or the armed
//                frame's window is open (until its last line, or the frame, ends)
//   P_window_done  window_done is high for one clock, the clock after the strobe of the
//                window's corner pixel (xmax, ymax) (where it would be, when decimated)
//   P_set_accepted set_accepted is high for one clock, the clock after a valid set completed
//   P_count      (REGULAR only) an armed frame strobes exactly (x1-x0+1)(y1-y0+1) pixels,
//                decimated ((x1-x0)/2+1)((y1-y0)/2+1); an unarmed frame none
// Covers C_*: a window touching each frame edge has its far corner strobed.
// Only ports are read: no internal register of the unit is named, so the harness holds
// whatever the RTL's inside looks like. The unbounded proofs (scripts/formal.sh) use ABC's
// PDR, which finds the inductive invariant itself. L_* are lemmas about the harness's own
// counters (REGULAR), for the k-induction of P_count.
//
// Defines: REGULAR        the camera sends full frames (exactly WIDTH pixels a line, HEIGHT
//                         lines a frame) and P_count is checked
//          COVER_BAD      the covers become assertions of their negation, for ABC's bmc3
`default_nettype none

module window_unit_props #(
    parameter integer WIDTH = 16,
    parameter integer HEIGHT = 16,
    parameter integer PIXEL_BITS = 8
) (
    input wire                  clock,
    input wire                  reset,
    input wire                  fval,
    input wire                  lval,
    input wire                  pixel_valid,
    input wire [PIXEL_BITS-1:0] pixel,
    input wire                  coord_strobe,
    input wire            [7:0] coord_data,
    input wire                  decimate
);
    localparam integer LARGEST = WIDTH > HEIGHT ? WIDTH : HEIGHT;
    localparam integer CB = $clog2(LARGEST);        // the unit's counter width
    localparam integer SB = CB + 1;                 // shadow counters: one bit more, saturating
    localparam [CB-1:0] CMAX = {CB{1'b1}};
    localparam [SB-1:0] SMAX = {SB{1'b1}};
    localparam integer WIDE = LARGEST > 256;
    localparam integer NBYTES = WIDE ? 8 : 4;
    localparam [2:0] LASTB = NBYTES - 1;
    localparam integer NB = 2 * SB;                 // pixel counts: up to 2^SB * 2^SB

    wire coord_ready, pixel_strobe, coord_error, armed, window_done, set_accepted;
    wire [PIXEL_BITS-1:0] pixel_out;

    window_unit #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .PIXEL_BITS(PIXEL_BITS)) dut (
        .clock(clock), .fval(fval), .lval(lval), .pixel(pixel),
        .coord_strobe(coord_strobe), .coord_data(coord_data), .coord_ready(coord_ready),
        .decimate(decimate), .pixel_strobe(pixel_strobe), .pixel_out(pixel_out),
        .coord_error(coord_error), .pixel_valid(pixel_valid), .reset(reset),
        .armed(armed), .window_done(window_done), .set_accepted(set_accepted));

    // -----------------------------------------------------------------------------------
    // Input history. The camera and the processor have no reset: these never clear.
    // -----------------------------------------------------------------------------------
    reg fv1 = 1'b0, fv2 = 1'b0, lv1 = 1'b0, lv2 = 1'b0, pv1 = 1'b0;
    reg rs1 = 1'b0, rs2 = 1'b0;
    reg cs1 = 1'b0, rdy1 = 1'b0, dc1 = 1'b0;
    reg [7:0] cd1 = 8'd0;
    reg [PIXEL_BITS-1:0] px1 = {PIXEL_BITS{1'b0}}, px2 = {PIXEL_BITS{1'b0}};
    always @(posedge clock) begin
        fv1 <= fval; fv2 <= fv1; lv1 <= lval; lv2 <= lv1; pv1 <= pixel_valid;
        rs1 <= reset; rs2 <= rs1;
        cs1 <= coord_strobe; rdy1 <= coord_ready; cd1 <= coord_data; dc1 <= decimate;
        px1 <= pixel; px2 <= px1;
    end

    // -----------------------------------------------------------------------------------
    // Assumptions: what the contract lets the camera and the processor do.
    // -----------------------------------------------------------------------------------
    always @(*) begin
        // Camera raster (the project's camera, hdl/src/sim/camera.rs, h_blank >= 2): a line
        // starts at least 2 clocks after the previous one ended, and a line of a frame at
        // least 2 clocks after fval rose (blanking lines, fval low, may start any time);
        // fval does not rise during a line. fval may fall during a line: what follows is no
        // pixel (fval & lval & pixel_valid).
        if (lval && !lv1) A_porch: assume (!lv2 && (!fval || (fv1 && fv2)));
        if (lval && lv1 && fval) A_line: assume (fv1);
        // Processor, four-phase: raise the strobe only with ready low; hold it (and the byte
        // and decimate with it) until ready is seen high. A reset also restarts the
        // processor: no strobe offered during reset.
        if (coord_strobe && !cs1) A_hs_raise: assume (!coord_ready);
        if (cs1 && !rdy1) A_hs_hold: assume (coord_strobe || reset);
        if (cs1 && coord_strobe && !rdy1) A_hs_stable: assume (coord_data == cd1 && decimate == dc1);
        if (reset) A_reset: assume (!coord_strobe);
    end

    // -----------------------------------------------------------------------------------
    // Shadow: the coordinate sets as the processor wrote them.
    // -----------------------------------------------------------------------------------
    wire rise = coord_ready && !rdy1;       // the processor sees its byte taken
    wire fall = !coord_ready && rdy1;
    reg [2:0] bidx = 3'd0;                  // which byte of the set this one is
    reg [63:0] sbytes = 64'd0;              // the set's bytes so far, byte i at [8i+7:8i]
    wire last = bidx == LASTB;
    wire done = rise && last;               // a set completes on this clock
    wire [15:0] n_x0 = WIDE ? {sbytes[7:0], sbytes[15:8]} : {8'd0, sbytes[7:0]};
    wire [15:0] n_x1 = WIDE ? {sbytes[23:16], sbytes[31:24]} : {8'd0, sbytes[15:8]};
    wire [15:0] n_y0 = WIDE ? {sbytes[39:32], sbytes[47:40]} : {8'd0, sbytes[23:16]};
    wire [15:0] n_y1 = WIDE ? {sbytes[55:48], coord_data} : {8'd0, coord_data};
    wire n_ok = n_x0 < n_x1 && {16'd0, n_x1} < WIDTH && n_y0 < n_y1 && {16'd0, n_y1} < HEIGHT;
    wire n_dec = decimate;                  // sampled with the set's last byte

    wire frise = fval && !fv1;              // the clock fval is first high
    reg pend = 1'b0;                        // a valid set waits for a frame
    reg [CB-1:0] p_x0 = 0, p_x1 = 0, p_y0 = 0, p_y1 = 0;
    reg p_dec = 1'b0;
    reg serr = 1'b0;                        // the last complete set was invalid
    reg inv = 1'b0;                         // an invalid set completed since the last frame start
    reg [CB-1:0] a_x0 = 0, a_x1 = 0, a_y0 = 0, a_y1 = 0;   // the armed (active) window
    reg a_dec = 1'b0;
    reg sarm = 1'b0;                        // the current frame is armed (fval rise .. fall)
    reg farm = 1'b0;                        // the last frame started was armed (till the next)
    reg finv = 1'b0;                        // the current frame follows an invalid set only
    reg cl = 1'b0;                          // no reset since the current frame started


    always @(posedge clock) begin
        if (reset) begin
            bidx <= 3'd0; sbytes <= 64'd0; pend <= 1'b0; serr <= 1'b0; inv <= 1'b0;
            p_x0 <= 0; p_x1 <= 0; p_y0 <= 0; p_y1 <= 0; p_dec <= 1'b0;
            a_x0 <= 0; a_x1 <= 0; a_y0 <= 0; a_y1 <= 0; a_dec <= 1'b0;
            sarm <= 1'b0; farm <= 1'b0; finv <= 1'b0; cl <= 1'b0;
        end else begin
            if (rise) begin
                sbytes[8*bidx +: 8] <= coord_data;
                bidx <= last ? 3'd0 : bidx + 3'd1;
            end
            if (done) begin
                serr <= !n_ok;
                if (n_ok) begin
                    pend <= 1'b1; inv <= 1'b0;
                    p_x0 <= n_x0[CB-1:0]; p_x1 <= n_x1[CB-1:0];
                    p_y0 <= n_y0[CB-1:0]; p_y1 <= n_y1[CB-1:0]; p_dec <= n_dec;
                end else begin
                    inv <= 1'b1;
                end
            end
            if (frise) begin
                // The arming margin (ARM_MARGIN = 1, hdl/src/window_unit.rs): the latest valid
                // set whose last byte was taken (coord_ready rose) on or before the clock fval
                // is first high arms this frame; one completed later waits for the next frame.
                sarm <= pend || (done && n_ok); farm <= pend || (done && n_ok);
                finv <= !(pend || (done && n_ok)) && (inv || (done && !n_ok));
                cl <= 1'b1; inv <= 1'b0; pend <= 1'b0;
                if (done && n_ok) begin
                    a_x0 <= n_x0[CB-1:0]; a_x1 <= n_x1[CB-1:0];
                    a_y0 <= n_y0[CB-1:0]; a_y1 <= n_y1[CB-1:0]; a_dec <= n_dec;
                end else if (pend) begin
                    a_x0 <= p_x0; a_x1 <= p_x1; a_y0 <= p_y0; a_y1 <= p_y1; a_dec <= p_dec;
                end
            end else if (!fval) begin
                sarm <= 1'b0;
            end
        end
    end

    // -----------------------------------------------------------------------------------
    // Shadow: where the camera is (no reset: the camera defines columns and rows).
    // -----------------------------------------------------------------------------------
    reg [SB-1:0] sx = 0;                    // pixels of this lval pulse before this clock
    reg [SB-1:0] sy = 0;                    // lines of this frame ended before this clock
    always @(posedge clock) begin
        sx <= !lval ? {SB{1'b0}} : (pixel_valid && sx != SMAX) ? sx + 1'b1 : sx;
        if (frise) sy <= {SB{1'b0}};
        else if (fval && fv1 && lv1 && !lval && sy != SMAX) sy <= sy + 1'b1;
    end

    wire pres = fval && lval && pixel_valid;   // a pixel is present (contract)
    wire [SB-1:0] ox = sx - a_x0;
    wire [SB-1:0] oy = sy - a_y0;
    wire in_x = sx >= a_x0 && sx <= a_x1;
    wire in_y = sy >= a_y0 && sy <= a_y1;
    wire grid = !a_dec || (!ox[0] && !oy[0]);
    wire inwin = sarm && pres && in_x && in_y && grid;   // this pixel is to be delivered

    // Two clocks later it is on pixel_strobe/pixel_out (docs/window-logic.md).
    reg e1 = 1'b0, e2 = 1'b0, sarm1 = 1'b0, sarm2 = 1'b0, finv1 = 1'b0, finv2 = 1'b0;
    reg [SB-1:0] sx1 = 0, sx2 = 0, sy1 = 0, sy2 = 0;
    always @(posedge clock) begin
        e1 <= !reset && inwin; e2 <= !reset && e1;
        sarm1 <= sarm; sarm2 <= sarm1; finv1 <= finv; finv2 <= finv1;
        sx1 <= sx; sx2 <= sx1; sy1 <= sy; sy2 <= sy1;
    end

    // -----------------------------------------------------------------------------------
    // Shadow of the status outputs: whether the armed frame's window is still open (its last
    // line, row a_y1, has not ended), its corner pixel (a_x1, a_y1) and the valid sets.
    // -----------------------------------------------------------------------------------
    reg wov = 1'b0;                         // the armed frame's last window line has ended
    wire live = sarm && !wov;               // the armed frame's window is open
    wire corner_now = sarm && pres && sx == a_x1 && sy == a_y1;
    reg live1 = 1'b0, acc1 = 1'b0, cn1 = 1'b0, cn2 = 1'b0, cn3 = 1'b0;
    always @(posedge clock) begin
        if (reset || frise) wov <= 1'b0;
        else if (sarm && fval && fv1 && lv1 && !lval && sy == a_y1) wov <= 1'b1;
        live1 <= !reset && live;
        acc1 <= !reset && done && n_ok;
        cn1 <= !reset && corner_now; cn2 <= !reset && cn1; cn3 <= !reset && cn2;
    end

    // -----------------------------------------------------------------------------------
    // Properties at the ports.
    // -----------------------------------------------------------------------------------
    reg [2:0] upw = 3'd0, dnw = 3'd0;       // clocks the current strobe edge has waited
    always @(posedge clock) begin
        upw <= (coord_strobe && !coord_ready) ? (upw == 3'd7 ? upw : upw + 3'd1) : 3'd0;
        dnw <= (!coord_strobe && coord_ready) ? (dnw == 3'd7 ? dnw : dnw + 3'd1) : 3'd0;
    end

    always @(*) begin
        P_inside: assert (!pixel_strobe || e2);
        P_data: assert (!pixel_strobe || pixel_out == px2);
        P_complete: assert (!e2 || pixel_strobe);
        P_bounds: assert (!pixel_strobe || (sx2 < WIDTH && sy2 < HEIGHT));
        P_noset: assert (!pixel_strobe || sarm2);
        P_invalid: assert (!pixel_strobe || !finv2);
        P_invalid_error: assert (coord_error == serr);
        P_hs_rise: assert (!rise || cs1);
        P_hs_fall: assert (!fall || !cs1);
        P_hs_answer_up: assert (!(coord_strobe && !coord_ready) || upw < 3'd4);
        P_hs_answer_down: assert (!(!coord_strobe && coord_ready) || dnw < 3'd4);
        // Status: armed from the clock after a valid set completes until the clock after its
        // window closes (STRBEN's two-clock lag behind the camera: live1), window_done on the
        // clock after the corner pixel's strobe, set_accepted on the clock after a valid set.
        P_armed: assert (armed == (pend || live || live1));
        P_window_done: assert (window_done == cn3);
        P_set_accepted: assert (set_accepted == acc1);
    end

    // -----------------------------------------------------------------------------------
    // Covers: a window touching each frame edge, its far corner actually strobed.
    // -----------------------------------------------------------------------------------
    reg [CB-1:0] b_x0 = 0, b_x1 = 0, b_y0 = 0, b_y1 = 0;   // a_* two clocks later
    reg b_dec = 1'b0;
    always @(posedge clock) begin
        b_x0 <= a_x0; b_x1 <= a_x1; b_y0 <= a_y0; b_y1 <= a_y1; b_dec <= a_dec;
    end
    wire corner = pixel_strobe && !b_dec && sx2 == b_x1 && sy2 == b_y1;
    wire c_left = corner && b_x0 == 0;
    wire c_right = corner && {1'b0, b_x1} == WIDTH - 1;
    wire c_top = corner && b_y0 == 0;
    wire c_bottom = corner && {1'b0, b_y1} == HEIGHT - 1;
    wire c_decimated = pixel_strobe && b_dec && sx2 == b_x0 + 2 && sy2 == b_y0 + 2;
`ifndef COVER_BAD
    always @(*) begin
        C_left: cover (c_left);
        C_right: cover (c_right);
        C_top: cover (c_top);
        C_bottom: cover (c_bottom);
        C_decimated: cover (c_decimated);
    end
`else
    // The same covers as "bad states", for a bit-level BMC (ABC bmc3) to reach.
    always @(*) begin
        C_left: assert (!c_left);
        C_right: assert (!c_right);
        C_top: assert (!c_top);
        C_bottom: assert (!c_bottom);
        C_decimated: assert (!c_decimated);
    end
`endif

`ifdef REGULAR
    // -----------------------------------------------------------------------------------
    // Full frames: exactly WIDTH pixels a line and HEIGHT lines a frame; P_count.
    // -----------------------------------------------------------------------------------
    always @(*) begin
        if (pres) R_width: assume (sx < WIDTH);
        if (fval && fv1 && lv1 && !lval) R_line: assume (sx == WIDTH);
        if (fval && lval && !lv1) R_height: assume (sy < HEIGHT);
        if (!fval && fv1) R_frame: assume (sy == HEIGHT);
    end

    reg fr1 = 1'b0, fr2 = 1'b0, cl1 = 1'b0, cl2 = 1'b0;
    reg [NB-1:0] icnt = 0, icnt1 = 0, icnt2 = 0;   // window pixels presented this frame
    reg [NB-1:0] ecnt = 0;                         // ... as the strobes should deliver them
    reg [NB-1:0] ocnt = 0;                         // strobes this frame
    always @(posedge clock) begin
        fr1 <= frise; fr2 <= fr1; cl1 <= cl; cl2 <= cl1;
        icnt <= frise ? {NB{1'b0}} : icnt + inwin;
        icnt1 <= icnt; icnt2 <= icnt1;
        ecnt <= fr2 ? {NB{1'b0}} : ecnt + e2;
        ocnt <= fr2 ? {NB{1'b0}} : ocnt + pixel_strobe;
    end

    wire [SB-1:0] dx = a_x1 - a_x0, dy = a_y1 - a_y0;
    wire [SB-1:0] nx = a_dec ? (dx >> 1) + 1'b1 : dx + 1'b1;
    wire [SB-1:0] ny = a_dec ? (dy >> 1) + 1'b1 : dy + 1'b1;
    wire [NB-1:0] nwin = nx * ny;                  // the window's pixel count
    // Window rows before row sy, window columns before column sx, and whether row sy is one.
    wire [SB-1:0] my = sy > a_y1 ? a_y1 + 1'b1 : sy;
    wire [SB-1:0] mx = sx > a_x1 ? a_x1 + 1'b1 : sx;
    wire [SB-1:0] rows = my <= a_y0 ? 0 : a_dec ? (my - a_y0 + 1'b1) >> 1 : my - a_y0;
    wire [SB-1:0] cols = mx <= a_x0 ? 0 : a_dec ? (mx - a_x0 + 1'b1) >> 1 : mx - a_x0;
    wire row_in = in_y && (!a_dec || !oy[0]);
    wire [NB-1:0] sofar = rows * nx + (row_in ? cols : 0);

    always @(*) begin
        L_ocnt: assert (ocnt == ecnt);
        if (cl && cl1 && cl2) L_ecnt: assert (ecnt == icnt2);
        if (cl) L_icnt: assert (icnt == (farm ? sofar : 0) && sy <= HEIGHT);
        if (cl && fval && fv1) L_sx: assert (sx <= WIDTH);
        if (cl && sarm) L_farm: assert (farm);
        if (cl && fval && fv1) L_sarm: assert (sarm == farm);
        if (cl && fval && lval) L_sy: assert (sy < HEIGHT);
        if (cl && !fval) L_sy_end: assert (sy == HEIGHT);
        if (pend) L_pending: assert (p_x0 < p_x1 && {1'b0, p_x1} < WIDTH
                                     && p_y0 < p_y1 && {1'b0, p_y1} < HEIGHT);
        if (farm) L_window: assert (a_x0 < a_x1 && {1'b0, a_x1} < WIDTH
                                    && a_y0 < a_y1 && {1'b0, a_y1} < HEIGHT);
        // The frame ended on the last clock: every strobe of it is counted.
        if (!fv1 && fv2 && cl) P_count: assert (ocnt == (farm ? nwin : 0));
    end
`endif
endmodule

`default_nettype wire
