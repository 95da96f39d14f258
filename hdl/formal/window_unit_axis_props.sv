// Formal harness for window_unit_axis (hdl/verilog/window_unit_axis.v): the AXI4-Stream rules
// as properties. Read with `read_verilog -formal -sv`; `scripts/formal.sh --axis` runs the
// checks (docs/formal.md).
//
// One window (WINDOWS = 1). Every input is free: the video stream (any tuser/tlast sequence,
// any tvalid gaps), the output's tready, reset, and AXI4-Lite writes to window 0's X, Y, CTRL,
// COMMIT and STATUS registers with any data. The harness reads the OVERFLOWS register over
// AXI4-Lite whenever its free arvalid asks. It reads only ports, and keeps a shadow of the
// contract in the RTL's header: the raster position of each beat, the set as written, the
// pending and active sets, and which beats of which frames the window must deliver.
//
// Properties (assert labels):
//   P_tready      s_axis_tready is high: the camera is never stalled
//   P_stable      an output beat offered and not taken stays offered, with tdata, tuser and
//                 tlast unchanged, until taken (or reset)
//   P_order       no more beats, tuser beats or tlast beats come out than the window's
//                 pixels, first pixels and row ends that went in
//   P_accounted   at each OVERFLOWS read: the window's beats in, minus those out, minus
//                 OVERFLOWS, lie in 0..FIFO_DEPTH+1 (what the FIFO and its output register
//                 hold), and are 0 when the output has been idle two clocks: no beat is lost
//                 without an overflow count
//   P_frames      at an idle read with OVERFLOWS 0: as many tuser beats came out as windows
//                 started (one tuser per window frame) and as many tlast beats as window rows
//   P_conserve    (define PROBES) on every clock: the window's beats accepted by the wrapper's
//                 window test, minus those out, minus OVERFLOWS, lie in 0..FIFO_DEPTH+1
//   P_drained     (define PROBES) and are 0 when no beat was offered for two clocks and none
//                 accepted before this one. Per clock and mod 2^NB, so that PDR proves them
//                 unbounded (P_accounted's counts and snapshots are for bounded checks)
// Cover C_rows: two window rows delivered and read back idle.
//
// Defines: COVER_BAD  the covers become assertions of their negation, for ABC's bmc3
//          PROBES     P_conserve, P_drained and their probes into the wrapper (see there)
`default_nettype none

module window_unit_axis_props #(
    parameter integer WIDTH = 4,
    parameter integer HEIGHT = 4,
    parameter integer PIXEL_BITS = 2,
    parameter integer FIFO_DEPTH = 2
) (
    input wire                  aclk,
    input wire                  aresetn,
    input wire [PIXEL_BITS-1:0] s_axis_tdata,
    input wire                  s_axis_tvalid,
    input wire                  s_axis_tuser,
    input wire                  s_axis_tlast,
    input wire                  m_axis_tready,
    input wire [11:0]           s_axil_awaddr,
    input wire                  s_axil_awvalid,
    input wire [31:0]           s_axil_wdata,
    input wire                  s_axil_wvalid,
    input wire                  s_axil_bready,
    input wire                  s_axil_arvalid
);
    localparam integer LARGEST = WIDTH > HEIGHT ? WIDTH : HEIGHT;
    localparam integer CB = $clog2(LARGEST);
    localparam integer SB = CB + 1;                 // shadow positions: one bit more, saturating
    localparam [SB-1:0] SMAX = {SB{1'b1}};
    localparam integer NB = 7;                      // beat counters: no wrap within the depths run

    wire                  s_axis_tready, m_axis_tvalid, m_axis_tuser, m_axis_tlast;
    wire [PIXEL_BITS-1:0] m_axis_tdata;
    wire s_axil_awready, s_axil_wready, s_axil_bvalid, s_axil_arready, s_axil_rvalid, irq;
    wire [1:0] s_axil_bresp, s_axil_rresp;
    wire [31:0] s_axil_rdata;

    window_unit_axis #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .PIXEL_BITS(PIXEL_BITS), .WINDOWS(1),
                       .FIFO_DEPTH(FIFO_DEPTH)) dut (
        .aclk(aclk), .aresetn(aresetn),
        .s_axis_tdata(s_axis_tdata), .s_axis_tvalid(s_axis_tvalid), .s_axis_tready(s_axis_tready),
        .s_axis_tuser(s_axis_tuser), .s_axis_tlast(s_axis_tlast),
        .m_axis_tdata(m_axis_tdata), .m_axis_tvalid(m_axis_tvalid), .m_axis_tready(m_axis_tready),
        .m_axis_tuser(m_axis_tuser), .m_axis_tlast(m_axis_tlast),
        .s_axil_awaddr(s_axil_awaddr), .s_axil_awvalid(s_axil_awvalid), .s_axil_awready(s_axil_awready),
        .s_axil_wdata(s_axil_wdata), .s_axil_wstrb(4'hF), .s_axil_wvalid(s_axil_wvalid),
        .s_axil_wready(s_axil_wready), .s_axil_bresp(s_axil_bresp), .s_axil_bvalid(s_axil_bvalid),
        .s_axil_bready(s_axil_bready), .s_axil_araddr(12'h38), .s_axil_arvalid(s_axil_arvalid),
        .s_axil_arready(s_axil_arready), .s_axil_rdata(s_axil_rdata), .s_axil_rresp(s_axil_rresp),
        .s_axil_rvalid(s_axil_rvalid), .s_axil_rready(1'b1), .irq(irq));

    wire reset = !aresetn;

    // Writes go to window 0's X, Y, CTRL, COMMIT and STATUS only, with coordinates below 32
    // (at 4x4 still far enough outside the sensor): a smaller problem.
    always @(*) begin
        A_data: assume (s_axil_wdata[15:5] == 0 && s_axil_wdata[31:21] == 0);
        if (s_axil_awvalid) A_addr: assume (s_axil_awaddr == 12'h20 || s_axil_awaddr == 12'h24 ||
                                            s_axil_awaddr == 12'h28 || s_axil_awaddr == 12'h2C ||
                                            s_axil_awaddr == 12'h30);
    end

    // -----------------------------------------------------------------------------------
    // Shadow of the contract: the set as written, pending and active; the raster.
    // -----------------------------------------------------------------------------------
    wire wr = s_axil_awvalid && s_axil_awready && s_axil_wvalid && s_axil_wready;
    reg [4:0] w_x0 = 0, w_x1 = 0, w_y0 = 0, w_y1 = 0;   // below 32 (A_data)
    reg w_dec = 1'b0, w_cont = 1'b0;
    wire w_ok = w_x0 < w_x1 && {27'd0, w_x1} < WIDTH && w_y0 < w_y1 && {27'd0, w_y1} < HEIGHT;
    wire commit = wr && s_axil_awaddr == 12'h2C && w_ok;   // a valid set committed now
    reg pend = 1'b0;
    reg [4:0] p_x0 = 0, p_x1 = 0, p_y0 = 0, p_y1 = 0;
    reg p_dec = 1'b0, p_cont = 1'b0;
    reg [4:0] a_x0 = 0, a_x1 = 0, a_y0 = 0, a_y1 = 0;
    reg a_dec = 1'b0, a_cont = 1'b0;
    reg live = 1'b0;                        // the window is open in this frame
    reg inf = 1'b0;                         // a tuser was taken since reset
    reg [SB-1:0] hx = 0, hy = 0;            // position of the next beat

    wire beat = !reset && s_axis_tvalid;
    wire sof = beat && s_axis_tuser;
    wire bin = beat && (sof || inf);        // a beat of a frame
    wire [SB-1:0] bx = sof ? {SB{1'b0}} : hx;
    wire [SB-1:0] by = sof ? {SB{1'b0}} : hy;
    // The set this beat is tested against: on a tuser beat, a commit on this same edge, else
    // the pending set, else the active one (which opens again only if continuous).
    wire [4:0] c_x0 = sof && commit ? w_x0 : sof && pend ? p_x0 : a_x0;
    wire [4:0] c_x1 = sof && commit ? w_x1 : sof && pend ? p_x1 : a_x1;
    wire [4:0] c_y0 = sof && commit ? w_y0 : sof && pend ? p_y0 : a_y0;
    wire [4:0] c_y1 = sof && commit ? w_y1 : sof && pend ? p_y1 : a_y1;
    wire c_dec = sof && commit ? w_dec : sof && pend ? p_dec : a_dec;
    wire c_cont = sof && commit ? w_cont : sof && pend ? p_cont : a_cont;
    wire c_live = sof ? (commit || pend || a_cont) : live;
    wire [5:0] ox = {{6-SB{1'b0}}, bx} - {1'b0, c_x0};
    wire [5:0] oy = {{6-SB{1'b0}}, by} - {1'b0, c_y0};
    // The last column and row delivered: one less when decimation skips x1 (or y1).
    wire [4:0] l_x1 = c_dec && (c_x1[0] != c_x0[0]) ? c_x1 - 5'd1 : c_x1;
    wire [4:0] l_y1 = c_dec && (c_y1[0] != c_y0[0]) ? c_y1 - 5'd1 : c_y1;
    wire hit = bin && c_live && bx >= c_x0 && bx <= c_x1 && by >= c_y0 && by <= c_y1
               && (!c_dec || (!ox[0] && !oy[0]));
    wire h_first = hit && bx == c_x0 && by == c_y0;
    wire h_last = hit && bx == l_x1;
    wire h_corner = h_last && by == l_y1;

    always @(posedge aclk) begin
        if (reset) begin
            w_x0 <= 0; w_x1 <= 0; w_y0 <= 0; w_y1 <= 0; w_dec <= 1'b0; w_cont <= 1'b0;
            pend <= 1'b0; live <= 1'b0; inf <= 1'b0; hx <= 0; hy <= 0;
            a_x0 <= 0; a_x1 <= 0; a_y0 <= 0; a_y1 <= 0; a_dec <= 1'b0; a_cont <= 1'b0;
        end else begin
            if (wr && s_axil_awaddr == 12'h20) begin w_x0 <= s_axil_wdata[4:0]; w_x1 <= s_axil_wdata[20:16]; end
            if (wr && s_axil_awaddr == 12'h24) begin w_y0 <= s_axil_wdata[4:0]; w_y1 <= s_axil_wdata[20:16]; end
            if (wr && s_axil_awaddr == 12'h28) begin w_dec <= s_axil_wdata[0]; w_cont <= s_axil_wdata[1]; end
            if (sof) begin
                a_x0 <= c_x0; a_x1 <= c_x1; a_y0 <= c_y0; a_y1 <= c_y1; a_dec <= c_dec; a_cont <= c_cont;
                live <= c_live;
                pend <= 1'b0;
            end else if (commit) begin
                p_x0 <= w_x0; p_x1 <= w_x1; p_y0 <= w_y0; p_y1 <= w_y1; p_dec <= w_dec; p_cont <= w_cont;
                pend <= 1'b1;
            end
            if (h_corner) live <= 1'b0;
            if (bin) begin
                inf <= 1'b1;
                hx <= s_axis_tlast ? {SB{1'b0}} : (bx == SMAX ? bx : bx + 1'b1);
                hy <= s_axis_tlast ? (by == SMAX ? by : by + 1'b1) : by;
            end
        end
    end

    // -----------------------------------------------------------------------------------
    // Counts: the window's beats in (one clock late, as the wrapper registers each beat
    // before its window test), and out.
    // -----------------------------------------------------------------------------------
    reg hit1 = 1'b0, first1 = 1'b0, last1 = 1'b0;
    reg [NB-1:0] n_in = 0, n_first = 0, n_last = 0, n_out = 0, n_user = 0, n_tlast = 0;
    wire take = m_axis_tvalid && m_axis_tready;
    always @(posedge aclk) begin
        hit1 <= hit; first1 <= h_first; last1 <= h_last;
        if (reset) begin
            n_in <= 0; n_first <= 0; n_last <= 0; n_out <= 0; n_user <= 0; n_tlast <= 0;
        end else begin
            n_in <= n_in + hit1; n_first <= n_first + first1; n_last <= n_last + last1;
            n_out <= n_out + take; n_user <= n_user + (take && m_axis_tuser);
            n_tlast <= n_tlast + (take && m_axis_tlast);
        end
    end

    // An OVERFLOWS read: the counts as they stood when its address was taken (rdata is the
    // register as it stood then), and whether the output was idle then and on the next clock.
    reg [NB-1:0] s_in = 0, s_first = 0, s_last = 0, s_out = 0, s_user = 0, s_tlast = 0;
    reg s_idle = 1'b0, s_ok = 1'b0;
    always @(posedge aclk) begin
        s_ok <= !reset && s_axil_arvalid && s_axil_arready;
        if (s_axil_arvalid && s_axil_arready) begin
            s_in <= n_in; s_first <= n_first; s_last <= n_last;
            s_out <= n_out; s_user <= n_user; s_tlast <= n_tlast;
            s_idle <= !m_axis_tvalid;
        end
    end
    wire [31:0] held = {25'd0, s_in} - {25'd0, s_out} - s_axil_rdata;   // in the FIFO and output register
    wire idle = s_ok && s_idle && !m_axis_tvalid;

    // History for the stream rule.
    reg v1 = 1'b0, r1 = 1'b0, u1 = 1'b0, l1 = 1'b0, rs1 = 1'b1;
    reg [PIXEL_BITS-1:0] d1 = 0;
    always @(posedge aclk) begin
        v1 <= m_axis_tvalid; r1 <= m_axis_tready; u1 <= m_axis_tuser; l1 <= m_axis_tlast;
        d1 <= m_axis_tdata; rs1 <= reset;
    end

    always @(*) begin
        P_tready: assert (s_axis_tready);
        if (v1 && !r1 && !rs1 && !reset)
            P_stable: assert (m_axis_tvalid && m_axis_tdata == d1 && m_axis_tuser == u1 && m_axis_tlast == l1);
        if (!reset) begin
            P_order: assert (n_out <= n_in && n_user <= n_first && n_tlast <= n_last);
        end
        if (s_ok && s_axil_rvalid && !reset) begin
            P_accounted: assert (!held[31] && held <= FIFO_DEPTH + 1 && (!idle || held == 0));
            if (idle && s_axil_rdata == 0)
                P_frames: assert (s_user == s_first && s_tlast == s_last);
        end
    end

`ifdef PROBES
    // Per clock, for an unbounded proof: every beat the wrapper's window test accepts is in its
    // FIFO or output register, out, or counted in OVERFLOWS. Two probes into the wrapper, tied
    // by scripts/formal.sh after flattening (yosys `connect`): its window test's verdict on the
    // beat in its b_ registers, and its overflow counter. (Which beats are the window's is
    // P_order's and the cocotb bench's business.) Counts are mod 2^NB: only differences matter.
    // The same for tuser and tlast marks (while nothing was dropped) kept PDR running over
    // 10 minutes, so those stay with P_frames, bounded.
    wire          probe_hit;            // dut.win[0].hit
    wire   [31:0] probe_drops;          // dut.win[0].drops (OVERFLOWS)
    reg  [NB-1:0] c_hit = 0, c_out = 0;
    reg           q_valid1 = 1'b0, q_hit1 = 1'b0;
    always @(posedge aclk) begin
        q_valid1 <= m_axis_tvalid; q_hit1 <= probe_hit && !reset;
        if (reset) begin c_hit <= 0; c_out <= 0; end
        else begin c_hit <= c_hit + probe_hit; c_out <= c_out + take; end
    end
    wire [NB-1:0] bal = c_hit - c_out - probe_drops[NB-1:0];   // beats held inside
    // OVERFLOWS saturates at 2^32-1 (the RTL's header); past that drops are not counted, so the
    // claim is for runs before it.
    always @(*) A_unsaturated: assume (probe_drops != 32'hFFFF_FFFF);
    always @(*)
        if (!reset && !rs1) begin
            P_conserve: assert (bal <= FIFO_DEPTH + 1);
            // No beat offered for two clocks and none accepted before this one: nothing held.
            if (!m_axis_tvalid && !q_valid1 && !q_hit1) P_drained: assert (bal == 0);
        end
`endif

    wire c_rows = s_ok && s_axil_rvalid && idle && s_tlast >= 2 && s_user >= 1;
`ifdef COVER_BAD
    always @(*) C_rows: assert (!c_rows);
`else
    always @(*) C_rows: cover (c_rows);
`endif
endmodule

`default_nettype wire
