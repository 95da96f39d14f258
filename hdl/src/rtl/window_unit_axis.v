// window_unit_axis: the window logic of the cooperative-windowing tracker (thesis 2.2.2,
// Fig. 2.1) as an AXI4-Stream video IP. One video stream in, WINDOWS cropped streams out, each
// window's rectangle set at run time over AXI4-Lite and applied at a start of frame.
//
// Input (AMD/Xilinx UG934 video): one pixel a beat, tuser[0] on a frame's first pixel, tlast on
// each line's last pixel. s_axis_tready is held high: a camera cannot wait, so the input never
// stalls, and a beat is taken on every clock with s_axis_tvalid high. Beats before the first
// tuser after reset are ignored. Lines are WIDTH pixels and frames HEIGHT lines; pixels beyond
// column WIDTH-1 or line HEIGHT-1 are never delivered.
//
// Output k: the pixels of window k's rectangle, in raster order, tuser on the window's first
// pixel, tlast on the last pixel of each window row; with decimation (the thesis Peripheral's
// 25% mode) only every second pixel of every second row, from (xmin, ymin). Output
// back-pressure is absorbed by a FIFO of FIFO_DEPTH beats (plus one output register) per
// window. A beat that finds its FIFO full is dropped, counted (OVERFLOWS) and flagged (STATUS
// bit 4); when the dropped beat carried tuser, the window's next beat carries it instead, so
// the frame start survives back-pressure. Nothing is dropped silently.
//
// Windows follow the bare unit's design (hdl/src/rtl/window_unit.v): saturating position
// counters, a window test against the active rectangle, and the 25% grid anchored at the
// window's (xmin, ymin) parity. One pair of counters serves all windows, since AXI4-Stream's
// tuser/tlast carry the raster that the unit recovers from FVAL/LVAL with two clocks of
// blanking per line, which AXI4-Stream does not give.
//
// Registers (32-bit words; wstrb is ignored, write whole words; unmapped addresses read 0), on
// aclk like everything here (axil_cdc.v puts them on a processor's own clock):
//   0x00 INFO        RO   [15:0] WINDOWS, [31:16] FIFO_DEPTH
//   0x04 GEOMETRY    RO   [15:0] WIDTH, [31:16] HEIGHT
//   0x08 IRQ_STATUS  W1C  bit k: window k done (its last pixel passed); irq = |(STATUS & ENABLE)
//   0x0C IRQ_ENABLE  RW   bit k: window k may raise irq
//   window k at B = 0x20 * (k + 1):
//   B+0x00 X         RW   [15:0] xmin, [31:16] xmax (inclusive)
//   B+0x04 Y         RW   [15:0] ymin, [31:16] ymax (inclusive)
//   B+0x08 CTRL      RW   bit 0 decimate (25%), bit 1 continuous (deliver every frame)
//   B+0x0C COMMIT    W    any write: X, Y, CTRL are checked and, if valid, latched for the
//                         next start of frame (a later commit replaces one not yet applied);
//                         if invalid, refused: INVALID is set and the previous set is kept
//   B+0x10 STATUS    R/W1C bit 0 armed (a set waits for a frame, owns this frame, or repeats),
//                         bit 1 busy (the window is open or its FIFO holds beats),
//                         bit 2 pending (a committed set waits for a start of frame),
//                         bit 3 invalid (the last commit was refused; cleared by a valid one),
//                         bit 4 overflow (sticky, write 1 to clear)
//   B+0x14 FRAMES    RO   windows completed (their last pixel passed, delivered or dropped)
//   B+0x18 OVERFLOWS RO   beats dropped on a full FIFO (saturates at 2^32-1)
// A set is valid iff xmin < xmax < WIDTH and ymin < ymax < HEIGHT, the bare unit's rule (thesis
// 2.2.1): a window is at least two pixels wide and high. A commit whose write
// handshake is on clock edge s applies to the first frame whose tuser beat is taken on edge s
// or later. A set without `continuous` delivers one window; with it, every frame until a
// commit replaces it. Contract and integration: docs/window-logic.md.
`timescale 1ns / 1ps
`default_nettype none

module window_unit_axis #(
    parameter integer WIDTH = 256,      // pixels per line (16..4096)
    parameter integer HEIGHT = 256,     // lines per frame (16..4096)
    parameter integer PIXEL_BITS = 8,   // bits per pixel (8..16); tdata is padded to whole bytes
    parameter integer WINDOWS = 4,      // window outputs (1..32)
    parameter integer FIFO_DEPTH = 32   // beats each output FIFO holds (a power of two, 2..4096)
) (
    input  wire                                    aclk,          // pixel clock: all logic on its rising edge
    input  wire                                    aresetn,       // synchronous, active low
    input  wire [((PIXEL_BITS+7)/8)*8-1:0]         s_axis_tdata,  // camera pixel (low PIXEL_BITS used)
    input  wire                                    s_axis_tvalid, // a pixel is on tdata
    output wire                                    s_axis_tready, // held high: the camera never waits
    input  wire                                    s_axis_tuser,  // start of frame: the frame's first pixel
    input  wire                                    s_axis_tlast,  // end of line: the line's last pixel
    output wire [WINDOWS*((PIXEL_BITS+7)/8)*8-1:0] m_axis_tdata,  // window k's pixel in slice k (zero padded)
    output wire [WINDOWS-1:0]                      m_axis_tvalid, // window k has a beat
    input  wire [WINDOWS-1:0]                      m_axis_tready, // window k's sink takes it
    output wire [WINDOWS-1:0]                      m_axis_tuser,  // the window's first pixel
    output wire [WINDOWS-1:0]                      m_axis_tlast,  // the last pixel of a window row
    input  wire [11:0]                             s_axil_awaddr, // AXI4-Lite register file
    input  wire                                    s_axil_awvalid,
    output wire                                    s_axil_awready,
    input  wire [31:0]                             s_axil_wdata,
    input  wire [3:0]                              s_axil_wstrb,  // ignored: whole words are written
    input  wire                                    s_axil_wvalid,
    output wire                                    s_axil_wready,
    output wire [1:0]                              s_axil_bresp,  // always OKAY
    output wire                                    s_axil_bvalid,
    input  wire                                    s_axil_bready,
    input  wire [11:0]                             s_axil_araddr,
    input  wire                                    s_axil_arvalid,
    output wire                                    s_axil_arready,
    output wire [31:0]                             s_axil_rdata,
    output wire [1:0]                              s_axil_rresp,  // always OKAY
    output wire                                    s_axil_rvalid,
    input  wire                                    s_axil_rready,
    output wire                                    irq            // a window whose IRQ_ENABLE bit is set is done
);
    localparam integer TW = ((PIXEL_BITS + 7) / 8) * 8;
    localparam integer LARGEST = WIDTH > HEIGHT ? WIDTH : HEIGHT;
    localparam integer CBITS = $clog2(LARGEST);
    // One bit more than a coordinate: a saturated position lies beyond every window.
    localparam integer PBITS = CBITS + 1;
    localparam [PBITS-1:0] POS_MAX = {PBITS{1'b1}};
    localparam integer ABITS = $clog2(FIFO_DEPTH);
    localparam integer WORDS = 8 * (WINDOWS + 1);

    wire reset = ~aresetn;
    assign s_axis_tready = 1'b1;

    // Input bits no logic reads: the byte lanes of the word-aligned AXI4-Lite addresses, wstrb
    // (whole words are written) and tdata's padding. Verilator's -Wall leaves signals named
    // *unused* alone (its --unused-regexp), so these sinks keep the lint clean at every size.
    wire unused_axil = &{1'b0, s_axil_awaddr[1:0], s_axil_araddr[1:0], s_axil_wstrb};
    generate
        if (TW > PIXEL_BITS) begin : tdata_pad
            wire unused_tdata = &{1'b0, s_axis_tdata[TW-1:PIXEL_BITS]};
        end
    endgenerate

    // ---------------------------------------------------------------------------------------
    // The raster: the position of each beat from tuser and tlast, registered with the beat.
    // ---------------------------------------------------------------------------------------
    reg                  in_frame = 1'b0;   // a tuser has been seen since reset
    reg      [PBITS-1:0] xnext = {PBITS{1'b0}};  // column of the next beat
    reg      [PBITS-1:0] ynext = {PBITS{1'b0}};  // line of the next beat
    reg                  b_valid = 1'b0;    // a beat of a frame is in the b_ registers
    reg                  b_sof = 1'b0;      // ... and it carried tuser
    reg      [PBITS-1:0] b_x = {PBITS{1'b0}};    // ... its column
    reg      [PBITS-1:0] b_y = {PBITS{1'b0}};    // ... its line
    reg [PIXEL_BITS-1:0] b_data = {PIXEL_BITS{1'b0}};  // ... its pixel

    wire sof = s_axis_tvalid & s_axis_tuser;
    wire [PBITS-1:0] bx = sof ? {PBITS{1'b0}} : xnext;
    wire [PBITS-1:0] by = sof ? {PBITS{1'b0}} : ynext;

    always @(posedge aclk) begin
        if (reset) begin
            in_frame <= 1'b0; xnext <= {PBITS{1'b0}}; ynext <= {PBITS{1'b0}};
            b_valid <= 1'b0; b_sof <= 1'b0;
        end else begin
            if (s_axis_tvalid & (sof | in_frame)) begin
                in_frame <= 1'b1;
                if (s_axis_tlast) begin
                    xnext <= {PBITS{1'b0}};
                    ynext <= by == POS_MAX ? by : by + 1'b1;
                end else begin
                    xnext <= bx == POS_MAX ? bx : bx + 1'b1;
                    ynext <= by;
                end
            end
            b_valid <= s_axis_tvalid & (sof | in_frame);
            b_sof <= sof;
        end
        b_x <= bx;
        b_y <= by;
        b_data <= s_axis_tdata[PIXEL_BITS-1:0];
    end

    // ---------------------------------------------------------------------------------------
    // AXI4-Lite: a write is taken when address and data are both offered and no response is
    // outstanding; a read when no read data is outstanding.
    // ---------------------------------------------------------------------------------------
    reg        bvalid = 1'b0;
    reg        rvalid = 1'b0;
    reg [31:0] rdata = 32'd0;
    reg [WINDOWS-1:0] irq_status = {WINDOWS{1'b0}};
    reg [WINDOWS-1:0] irq_enable = {WINDOWS{1'b0}};
    wire wr = s_axil_awvalid & s_axil_wvalid & ~bvalid;
    wire rd = s_axil_arvalid & ~rvalid;
    wire [9:0] wr_word = s_axil_awaddr[11:2];
    wire [9:0] rd_word = s_axil_araddr[11:2];
    wire [32*WORDS-1:0] words;               // every register as read, word i at [32i +: 32]
    wire [WINDOWS-1:0] done;                 // window k's last pixel passed on this edge

    wire [WINDOWS-1:0] irq_clear = (wr & (wr_word == 10'd2)) ? s_axil_wdata[WINDOWS-1:0] : {WINDOWS{1'b0}};
    assign words[0 +: 64] = {HEIGHT[15:0], WIDTH[15:0], FIFO_DEPTH[15:0], WINDOWS[15:0]};
    assign words[64 +: WINDOWS] = irq_status;
    assign words[96 +: WINDOWS] = irq_enable;
    generate
        if (WINDOWS < 32) begin : pad
            assign words[64 + WINDOWS +: 32 - WINDOWS] = {32-WINDOWS{1'b0}};
            assign words[96 + WINDOWS +: 32 - WINDOWS] = {32-WINDOWS{1'b0}};
        end
    endgenerate
    assign words[128 +: 128] = 128'd0;

    always @(posedge aclk) begin
        if (reset) begin
            bvalid <= 1'b0; rvalid <= 1'b0; rdata <= 32'd0;
            irq_status <= {WINDOWS{1'b0}}; irq_enable <= {WINDOWS{1'b0}};
        end else begin
            if (wr) bvalid <= 1'b1;
            else if (s_axil_bready) bvalid <= 1'b0;
            if (rd) begin
                rvalid <= 1'b1;
                rdata <= {22'd0, rd_word} < WORDS ? words[32*rd_word +: 32] : 32'd0;
            end else if (s_axil_rready) rvalid <= 1'b0;
            if (wr & (wr_word == 10'd3)) irq_enable <= s_axil_wdata[WINDOWS-1:0];
            // A done on the clearing edge stays set: an interrupt is never lost.
            irq_status <= (irq_status & ~irq_clear) | done;
        end
    end

    assign s_axil_awready = wr;
    assign s_axil_wready = wr;
    assign s_axil_bresp = 2'b00;
    assign s_axil_bvalid = bvalid;
    assign s_axil_arready = rd;
    assign s_axil_rdata = rdata;
    assign s_axil_rresp = 2'b00;
    assign s_axil_rvalid = rvalid;
    assign irq = |(irq_status & irq_enable);

    // ---------------------------------------------------------------------------------------
    // The windows: each its registers, its window test and its FIFO.
    // ---------------------------------------------------------------------------------------
    genvar k;
    generate
        for (k = 0; k < WINDOWS; k = k + 1) begin : win
            wire sel = wr & (wr_word[9:3] == k + 1);
            // Written: the set as the processor writes it, checked at COMMIT.
            reg [15:0] sx0 = 16'd0, sx1 = 16'd0, sy0 = 16'd0, sy1 = 16'd0;
            reg        sdec = 1'b0, scont = 1'b0;
            // Pending: a committed set waiting for a start of frame. x1/y1 hold the last
            // delivered column and row (the decimation grid's, when decimated).
            reg [CBITS-1:0] px0 = {CBITS{1'b0}}, px1 = {CBITS{1'b0}}, py0 = {CBITS{1'b0}}, py1 = {CBITS{1'b0}};
            reg             pdec = 1'b0, pcont = 1'b0, pend = 1'b0;
            // Active: the set this frame uses.
            reg [CBITS-1:0] ax0 = {CBITS{1'b0}}, ax1 = {CBITS{1'b0}}, ay0 = {CBITS{1'b0}}, ay1 = {CBITS{1'b0}};
            reg             adec = 1'b0, acont = 1'b0;
            reg             live = 1'b0;     // the window is open in this frame
            reg             carry = 1'b0;    // a dropped tuser waits for the next beat pushed
            reg             invalid = 1'b0;  // the last commit was refused
            reg             ovf = 1'b0;      // a beat was dropped (sticky)
            reg      [31:0] frames = 32'd0;
            reg      [31:0] drops = 32'd0;

            wire ok = (sx0 < sx1) && ({16'd0, sx1} < WIDTH) && (sy0 < sy1) && ({16'd0, sy1} < HEIGHT);
            wire commit = sel & (wr_word[2:0] == 3'd3);
            // The last column and row on the decimation grid: x1 - 1 when x1 - x0 is odd.
            wire [15:0] lx1 = (sdec & (sx1[0] ^ sx0[0])) ? sx1 - 16'd1 : sx1;
            wire [15:0] ly1 = (sdec & (sy1[0] ^ sy0[0])) ? sy1 - 16'd1 : sy1;
            // Latched only when the set is valid (x1 < WIDTH), so the bits above CBITS are 0.
            // (Computing lx1 in CBITS bits instead maps to about 90 more SB_LUT4 at 4 windows.)
            wire unused_l1 = &{1'b0, lx1[15:CBITS], ly1[15:CBITS]};

            // The set for the beat in b_: the pending one on the start of frame it applies to.
            wire take = b_valid & b_sof & pend;
            wire [PBITS-1:0] cx0 = {1'b0, take ? px0 : ax0};
            wire [PBITS-1:0] cx1 = {1'b0, take ? px1 : ax1};
            wire [PBITS-1:0] cy0 = {1'b0, take ? py0 : ay0};
            wire [PBITS-1:0] cy1 = {1'b0, take ? py1 : ay1};
            wire             cdec = take ? pdec : adec;
            wire             open = b_valid & (b_sof ? (pend | acont) : live);
            wire hit = open && (b_x >= cx0) && (b_x <= cx1) && (b_y >= cy0) && (b_y <= cy1)
                       && (~cdec | ((b_x[0] == cx0[0]) & (b_y[0] == cy0[0])));
            wire first = hit && (b_x == cx0) && (b_y == cy0);
            wire rlast = hit && (b_x == cx1);
            wire wlast = rlast && (b_y == cy1);
            assign done[k] = wlast;

            // FIFO: FIFO_DEPTH entries of {tuser, tlast, pixel}, read synchronously (block RAM)
            // into the output register q.
            reg [PIXEL_BITS+1:0] mem [0:FIFO_DEPTH-1];
            reg      [ABITS:0] wptr = {ABITS+1{1'b0}}, rptr = {ABITS+1{1'b0}};
            reg [PIXEL_BITS+1:0] q = {PIXEL_BITS+2{1'b0}};
            reg                  qvalid = 1'b0;
            wire     [ABITS:0] used = wptr - rptr;
            wire full = used[ABITS];            // used == FIFO_DEPTH, the most it holds
            wire empty = wptr == rptr;
            wire load = ~empty & (~qvalid | m_axis_tready[k]);

            always @(posedge aclk) begin
                if (reset) begin
                    sx0 <= 16'd0; sx1 <= 16'd0; sy0 <= 16'd0; sy1 <= 16'd0; sdec <= 1'b0; scont <= 1'b0;
                    px0 <= {CBITS{1'b0}}; px1 <= {CBITS{1'b0}}; py0 <= {CBITS{1'b0}}; py1 <= {CBITS{1'b0}};
                    pdec <= 1'b0; pcont <= 1'b0; pend <= 1'b0;
                    ax0 <= {CBITS{1'b0}}; ax1 <= {CBITS{1'b0}}; ay0 <= {CBITS{1'b0}}; ay1 <= {CBITS{1'b0}};
                    adec <= 1'b0; acont <= 1'b0; live <= 1'b0; carry <= 1'b0;
                    invalid <= 1'b0; ovf <= 1'b0; frames <= 32'd0; drops <= 32'd0;
                    wptr <= {ABITS+1{1'b0}}; rptr <= {ABITS+1{1'b0}}; qvalid <= 1'b0;
                end else begin
                    // Register writes.
                    if (sel & (wr_word[2:0] == 3'd0)) begin sx0 <= s_axil_wdata[15:0]; sx1 <= s_axil_wdata[31:16]; end
                    if (sel & (wr_word[2:0] == 3'd1)) begin sy0 <= s_axil_wdata[15:0]; sy1 <= s_axil_wdata[31:16]; end
                    if (sel & (wr_word[2:0] == 3'd2)) begin sdec <= s_axil_wdata[0]; scont <= s_axil_wdata[1]; end
                    if (sel & (wr_word[2:0] == 3'd4) & s_axil_wdata[4]) ovf <= 1'b0;

                    // Start of frame: the pending set becomes the active one; the window opens
                    // for it, or for the active set when that repeats.
                    if (b_valid & b_sof) begin
                        if (pend) begin
                            ax0 <= px0; ax1 <= px1; ay0 <= py0; ay1 <= py1; adec <= pdec; acont <= pcont;
                            pend <= 1'b0;
                        end
                        live <= pend | acont;
                        carry <= 1'b0;
                    end
                    // A commit on the same edge waits for the next frame.
                    if (commit) begin
                        invalid <= ~ok;
                        if (ok) begin
                            px0 <= sx0[CBITS-1:0]; px1 <= lx1[CBITS-1:0];
                            py0 <= sy0[CBITS-1:0]; py1 <= ly1[CBITS-1:0];
                            pdec <= sdec; pcont <= scont; pend <= 1'b1;
                        end
                    end
                    if (wlast) begin
                        live <= 1'b0;
                        frames <= frames + 32'd1;
                    end

                    // Push the window's beat, or count it dropped.
                    if (hit) begin
                        if (full) begin
                            ovf <= 1'b1;
                            if (drops != 32'hFFFF_FFFF) drops <= drops + 32'd1;
                            carry <= carry | first;
                        end else begin
                            wptr <= wptr + 1'b1;
                            carry <= 1'b0;
                        end
                    end
                    // Pop into the output register.
                    if (load) begin
                        rptr <= rptr + 1'b1;
                        qvalid <= 1'b1;
                    end else if (m_axis_tready[k]) qvalid <= 1'b0;
                end
                if (hit & ~full & ~reset) mem[wptr[ABITS-1:0]] <= {first | carry, rlast, b_data};
                if (load & ~reset) q <= mem[rptr[ABITS-1:0]];
            end

            wire armed = pend | live | acont;
            wire busy = live | ~empty | qvalid;
            assign words[32*8*(k+1) +: 256] = {32'd0, drops, frames,
                                               27'd0, ovf, invalid, pend, busy, armed,
                                               32'd0, 30'd0, scont, sdec, sy1, sy0, sx1, sx0};
            assign m_axis_tdata[TW*k +: PIXEL_BITS] = q[PIXEL_BITS-1:0];
            if (TW > PIXEL_BITS) begin : pad
                assign m_axis_tdata[TW*k + PIXEL_BITS +: TW - PIXEL_BITS] = {TW-PIXEL_BITS{1'b0}};
            end
            assign m_axis_tvalid[k] = qvalid;
            assign m_axis_tuser[k] = q[PIXEL_BITS+1];
            assign m_axis_tlast[k] = q[PIXEL_BITS];
        end
    endgenerate
endmodule

`default_nettype wire
