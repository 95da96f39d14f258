// coopwin_ice40_axis_top: the AXI4-Stream window IP (window_unit_axis) on the iCE40-HX8K
// breakout board (ct256), as an example integration: the OV7670-style camera's pins become
// an AXI4-Stream video source (coopwin_dvp_axis), window_unit_axis crops WINDOWS windows out of
// it, each window's cropped stream is captured into its own buffer, and a host PC on the
// FT2232H UART plays the window processor (thesis 2.2.2): it writes and reads the IP's
// AXI4-Lite registers through a bridge and reads the captured windows.
// Same board, pins and clocks as coopwin_ice40_top (docs/board.md); it uses that file's UART,
// SCCB and synchroniser modules. Build: scripts/board-fpga.sh --axis. NOT run on hardware.
//
// Clock domains: as coopwin_ice40_top. clk12: UART, command parser, SCCB, buffer read side.
// cam_pclk: camera inputs, coopwin_dvp_axis, window_unit_axis, its AXI4-Lite master, the
// capture side. One crossing (CDC, bundled data): a register access goes 12 MHz -> pclk as
// a_write/a_addr/a_wdata with a_req; the result comes back as a_rdata with a_ack (four-phase:
// each side changes its bus only while the other's level says it is not being read).
// The capture buffers are dual-clock block RAMs; the host reads one only when its window is
// finished (STATUS armed = 0 and busy = 0, read over the same bridge), so no buffer is read
// while its write side writes, as long as the host keeps to that.
//
// Host protocol (multi-byte fields big-endian, no checksums; UART framing is 8N1):
//   'w' a[15:8] a[7:0] d[31:24] d[23:16] d[15:8] d[7:0]  register write   -> 'K'
//   'r' a[15:8] a[7:0]                                   register read    -> d[31:24] .. d[7:0]
//   'B' k n[15:8] n[7:0]                                 window k's buffer -> n bytes, pixels 0..n-1
//   'S' reg value                                        SCCB write       -> 'K' when done
//   Other bytes in idle, and every byte while a command runs, are dropped.
// Register map: a < 0x1000 is window_unit_axis's (its header: INFO, GEOMETRY, IRQ_*, and per
// window X, Y, CTRL, COMMIT, STATUS, FRAMES, OVERFLOWS), and two of this top's own:
//   0x1000 + 4k CAPTURED k  R: [15:0] beats taken since the last tuser beat, [27:16] tlast
//                           beats among them, [31:28] tuser beats (mod 16); W: clears it
//   0x1100      THROTTLE    RW: bit k set = window k's tready follows a pseudo-random bit (about
//                           half the clocks), a sink that stalls, to show the FIFO at work
// If PCLK stops, a register access waits for it (there is no timeout in this example).
`default_nettype none

module coopwin_ice40_axis_top #(
    parameter integer WIDTH = 640,          // pixels per line (raw mode: one byte a pixel)
    parameter integer HEIGHT = 480,
    parameter integer WINDOWS = 2,          // window outputs (1..5: one LED each)
    parameter integer FIFO_DEPTH = 32,      // beats each window's FIFO holds
    parameter integer BUF_AW = 11,          // each capture buffer 2**11 pixels x 8 bits: 4 BRAMs
    parameter integer CLKS_PER_BIT = 4,     // 12 MHz / 4 = 3 Mbaud
    parameter integer SCCB_QUARTER = 30,    // 100 kHz SIOC
    parameter [0:0]   VSYNC_ACTIVE_HIGH = 1'b1  // OV7670 default: fval = ~VSYNC
) (
    input  wire       clk12,        // J3: 12 MHz oscillator (GBIN)
    input  wire       uart_rx,      // B10: from the FT2232H channel B TXD
    output wire       uart_tx,      // B12: to the FT2232H channel B RXD
    input  wire       cam_pclk,     // H16: camera PCLK (GBIN)
    input  wire       cam_vsync,    // camera VSYNC
    input  wire       cam_href,     // camera HREF
    input  wire [7:0] cam_d,        // camera D[7:0]
    output wire       cam_xclk,     // 12 MHz to the camera's XCLK
    output wire       cam_reset_n,  // camera RESET (active low): held inactive
    output wire       cam_pwdn,     // camera PWDN (active high): held inactive
    output wire       cam_sioc,     // SCCB clock
    inout  wire       cam_siod,     // SCCB data: driven low or released (pull-up)
    output wire [7:0] led           // status LEDs D2..D9
);
    localparam integer DEPTH = 1 << BUF_AW;

    wire clk, pclk;
`ifdef SYNTHESIS
    SB_GB_IO #(.PIN_TYPE(6'b000001)) clk12_gb (.PACKAGE_PIN(clk12), .GLOBAL_BUFFER_OUTPUT(clk));
    SB_GB_IO #(.PIN_TYPE(6'b000001)) pclk_gb (.PACKAGE_PIN(cam_pclk), .GLOBAL_BUFFER_OUTPUT(pclk));
    SB_IO #(.PIN_TYPE(6'b010001)) xclk_io (.PACKAGE_PIN(cam_xclk), .OUTPUT_CLK(clk),
        .CLOCK_ENABLE(1'b1), .D_OUT_0(1'b1), .D_OUT_1(1'b0));
`else
    assign clk = clk12;
    assign pclk = cam_pclk;
    assign cam_xclk = clk;
`endif
    assign cam_reset_n = 1'b1;
    assign cam_pwdn = 1'b0;

    // CDC bundle, 12 MHz -> pclk: set before a_req rises, held until a_ack has come back.
    reg        a_req = 1'b0;
    reg        a_write = 1'b0;
    reg [15:0] a_addr = 16'd0;
    reg [31:0] a_wdata = 32'd0;
    // CDC bundle, pclk -> 12 MHz: set before a_ack rises, held until a_req has fallen.
    reg        a_ack = 1'b0;
    reg [31:0] a_rdata = 32'd0;

    // =======================================================================================
    // Pixel-clock domain
    // =======================================================================================
    // Camera inputs on PCLK's rising edge (the OV7670 changes them on the falling edge).
    reg       fv0 = 1'b0, hr0 = 1'b0;
    reg [7:0] d0 = 8'd0;
    always @(posedge pclk) begin
        fv0 <= VSYNC_ACTIVE_HIGH ? ~cam_vsync : cam_vsync;
        hr0 <= cam_href;
        d0 <= cam_d;
    end

    wire [7:0] v_tdata;
    wire       v_tvalid, v_tuser, v_tlast;
    coopwin_dvp_axis u_dvp (
        .clk(pclk), .fval(fv0), .lval(hr0), .data(d0),
        .m_axis_tdata(v_tdata), .m_axis_tvalid(v_tvalid),
        .m_axis_tuser(v_tuser), .m_axis_tlast(v_tlast));

    wire [8*WINDOWS-1:0] w_tdata;
    wire [WINDOWS-1:0]   w_tvalid, w_tready, w_tuser, w_tlast;
    reg         awvalid = 1'b0, arvalid = 1'b0;
    wire        awready, bvalid, arready, rvalid, irq;
    wire [31:0] rdata;
    window_unit_axis #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .PIXEL_BITS(8), .WINDOWS(WINDOWS),
                       .FIFO_DEPTH(FIFO_DEPTH)) u_axis (
        .aclk(pclk), .aresetn(1'b1),
        .s_axis_tdata(v_tdata), .s_axis_tvalid(v_tvalid), .s_axis_tready(),  // always 1
        .s_axis_tuser(v_tuser), .s_axis_tlast(v_tlast),
        .m_axis_tdata(w_tdata), .m_axis_tvalid(w_tvalid), .m_axis_tready(w_tready),
        .m_axis_tuser(w_tuser), .m_axis_tlast(w_tlast),
        .s_axil_awaddr(a_addr[11:0]), .s_axil_awvalid(awvalid), .s_axil_awready(awready),
        .s_axil_wdata(a_wdata), .s_axil_wstrb(4'hF), .s_axil_wvalid(awvalid), .s_axil_wready(),
        .s_axil_bresp(), .s_axil_bvalid(bvalid), .s_axil_bready(1'b1),
        .s_axil_araddr(a_addr[11:0]), .s_axil_arvalid(arvalid), .s_axil_arready(arready),
        .s_axil_rdata(rdata), .s_axil_rresp(), .s_axil_rvalid(rvalid), .s_axil_rready(1'b1),
        .irq(irq));

    // The AXI4-Lite master: one access per a_req (the synchronised level), then a_ack until
    // a_req falls. Addresses from 0x1000 are this top's own registers, answered at once.
    // window_unit_axis takes a write's address and data together (awready = wready), so one
    // valid drives both; bready and rready are held high.
    wire a_req_p;
    coopwin_sync2 sync_areq (.clk(pclk), .d(a_req), .q(a_req_p));
    localparam [1:0] M_IDLE = 2'd0, M_WRITE = 2'd1, M_READ = 2'd2, M_RESP = 2'd3;
    reg  [1:0] mst = M_IDLE;
    reg [WINDOWS-1:0] throttle = {WINDOWS{1'b0}};
    wire local_reg = a_addr[15:12] != 4'd0;
    wire [WINDOWS-1:0] cap_clear;
    wire [32*WINDOWS-1:0] captured;
    wire [31:0] local_rdata = a_addr[8] ? {{(32-WINDOWS){1'b0}}, throttle}
                            : (a_addr[2+:5] < WINDOWS) ? captured[32*a_addr[2+:5] +: 32] : 32'd0;
    always @(posedge pclk) begin
        case (mst)
            M_IDLE:
                if (a_ack) begin
                    if (~a_req_p) a_ack <= 1'b0;
                end else if (a_req_p) begin
                    if (local_reg) begin
                        if (a_write & a_addr[8]) throttle <= a_wdata[WINDOWS-1:0];
                        a_rdata <= local_rdata;
                        a_ack <= 1'b1;
                    end else if (a_write) begin
                        awvalid <= 1'b1; mst <= M_WRITE;
                    end else begin
                        arvalid <= 1'b1; mst <= M_READ;
                    end
                end
            M_WRITE:
                if (awready) begin awvalid <= 1'b0; mst <= M_RESP; end
            M_READ:
                if (arready) begin arvalid <= 1'b0; mst <= M_RESP; end
            default:  // M_RESP: bready and rready are held high
                if (bvalid | rvalid) begin
                    a_rdata <= rdata; a_ack <= 1'b1; mst <= M_IDLE;
                end
        endcase
    end
    // A write to CAPTURED k clears it, on the edge the access is taken.
    wire local_write = (mst == M_IDLE) & ~a_ack & a_req_p & local_reg & a_write & ~a_addr[8];

    // A pseudo-random bit per window for THROTTLE (16-bit Fibonacci LFSR, x^16+x^14+x^13+x^11+1).
    reg [15:0] lfsr = 16'hACE1;
    always @(posedge pclk) lfsr <= {lfsr[14:0], lfsr[15] ^ lfsr[13] ^ lfsr[12] ^ lfsr[10]};

    // Capture: each window's beats into its buffer, from the tuser beat on, in order.
    wire [WINDOWS*8-1:0] buf_rdata;
    wire [BUF_AW-1:0] buf_raddr;
    genvar k;
    generate
        for (k = 0; k < WINDOWS; k = k + 1) begin : cap
            assign w_tready[k] = ~throttle[k] | lfsr[3*k];
            assign cap_clear[k] = local_write & (a_addr[2+:5] == k);
            wire take = w_tvalid[k] & w_tready[k];
            reg [15:0] beats = 16'd0;
            reg [11:0] rows = 12'd0;
            reg  [3:0] tusers = 4'd0;
            wire [15:0] idx = w_tuser[k] ? 16'd0 : beats;
            always @(posedge pclk)
                if (cap_clear[k]) begin
                    beats <= 16'd0; rows <= 12'd0; tusers <= 4'd0;
                end else if (take) begin
                    if (~&idx) beats <= idx + 16'd1;
                    rows <= (w_tuser[k] ? 12'd0 : rows) + {11'd0, w_tlast[k]};
                    tusers <= tusers + {3'd0, w_tuser[k]};
                end
            assign captured[32*k +: 32] = {tusers, rows, beats};

            reg [7:0] mem [0:DEPTH-1];
            reg [7:0] rd = 8'd0;
            always @(posedge pclk)
                if (take & (idx < DEPTH)) mem[idx[BUF_AW-1:0]] <= w_tdata[8*k +: 8];
            always @(posedge clk)
                rd <= mem[buf_raddr];
            assign buf_rdata[8*k +: 8] = rd;
        end
    endgenerate

    // =======================================================================================
    // 12 MHz domain
    // =======================================================================================
    wire a_ack_12;
    coopwin_sync2 sync_aack (.clk(clk), .d(a_ack), .q(a_ack_12));

    wire       rx_valid;
    wire [7:0] rx_data;
    coopwin_uart_rx #(.CLKS_PER_BIT(CLKS_PER_BIT)) u_rx (
        .clk(clk), .rx(uart_rx), .valid(rx_valid), .data(rx_data));
    reg        tx_valid;
    reg  [7:0] tx_data;
    wire       tx_ready;
    coopwin_uart_tx #(.CLKS_PER_BIT(CLKS_PER_BIT)) u_tx (
        .clk(clk), .valid(tx_valid), .data(tx_data), .ready(tx_ready), .tx(uart_tx));
    wire tx_go = tx_valid & tx_ready;

    reg        sccb_start = 1'b0;
    wire       sccb_done;

    localparam [2:0] S_IDLE = 3'd0, S_ARG = 3'd1, S_BUS = 3'd2, S_SCCB = 3'd3, S_REPLY = 3'd4,
                     S_BUF0 = 3'd5, S_BUF = 3'd6;
    reg  [2:0] st = S_IDLE;
    reg  [7:0] cmd = 8'd0;
    reg  [2:0] argn = 3'd0;         // argument bytes still to come
    reg [47:0] args = 48'd0;        // the arguments, shifted in, last byte lowest
    reg  [1:0] hs = 2'd0;           // bridge handshake phase
    reg [31:0] reply = 32'd0;       // reply bytes, highest first
    reg  [2:0] nreply = 3'd0;       // reply bytes left
    reg  [7:0] bsel = 8'd0;         // buffer being sent
    reg [15:0] bleft = 16'd0;       // its bytes left
    reg [BUF_AW-1:0] pidx = {BUF_AW{1'b0}};
    assign buf_raddr = pidx;
    wire [7:0] buf_byte = (bsel < WINDOWS) ? buf_rdata[8*bsel +: 8] : 8'd0;   // no such window: 0s

    coopwin_sccb_write #(.QUARTER(SCCB_QUARTER)) u_sccb (
        .clk(clk), .start(sccb_start), .reg_addr(args[15:8]), .value(args[7:0]),
        .done(sccb_done), .sioc(cam_sioc), .siod(cam_siod));

    always @* begin
        tx_valid = (st == S_REPLY) | (st == S_BUF);
        tx_data = (st == S_BUF) ? buf_byte : reply[31:24];
    end

    always @(posedge clk) begin
        sccb_start <= 1'b0;
        case (st)
            S_IDLE:
                if (rx_valid) begin
                    cmd <= rx_data;
                    case (rx_data)
                        8'h77: begin argn <= 3'd6; st <= S_ARG; end   // 'w'
                        8'h72: begin argn <= 3'd2; st <= S_ARG; end   // 'r'
                        8'h42: begin argn <= 3'd3; st <= S_ARG; end   // 'B'
                        8'h53: begin argn <= 3'd2; st <= S_ARG; end   // 'S'
                        default: ;
                    endcase
                end
            S_ARG:
                if (rx_valid) begin
                    args <= {args[39:0], rx_data};
                    argn <= argn - 3'd1;
                    if (argn == 3'd1) begin
                        hs <= 2'd0;
                        pidx <= {BUF_AW{1'b0}};   // so the buffer's read register holds pixel 0 in S_BUF
                        if (cmd == 8'h53) begin sccb_start <= 1'b1; st <= S_SCCB; end
                        else if (cmd == 8'h42) st <= S_BUF0;
                        else st <= S_BUS;
                    end
                end
            S_BUS:
                // CDC: the bundle is set one clock before a_req rises and held until a_ack
                // has been seen high and then low again through two flip-flops.
                case (hs)
                    2'd0: begin
                        a_write <= cmd == 8'h77;
                        a_addr <= (cmd == 8'h77) ? args[47:32] : args[15:0];
                        a_wdata <= args[31:0];
                        hs <= 2'd1;
                    end
                    2'd1: begin a_req <= 1'b1; hs <= 2'd2; end
                    2'd2: if (a_ack_12) begin
                        a_req <= 1'b0; hs <= 2'd3;
                        reply <= a_write ? 32'h4B00_0000 : a_rdata;   // 'K' or the word
                        nreply <= a_write ? 3'd1 : 3'd4;
                    end
                    default: if (~a_ack_12) st <= S_REPLY;
                endcase
            S_SCCB:
                if (sccb_done) begin reply <= 32'h4B00_0000; nreply <= 3'd1; st <= S_REPLY; end
            S_REPLY:
                if (tx_go) begin
                    reply <= {reply[23:0], 8'd0};
                    nreply <= nreply - 3'd1;
                    if (nreply == 3'd1) st <= S_IDLE;
                end
            S_BUF0: begin
                // the window and the byte count (pixel 0 is already in its read register)
                bsel <= args[23:16]; bleft <= args[15:0];
                st <= (args[15:0] == 16'd0) ? S_IDLE : S_BUF;
            end
            default:  // S_BUF: buf_rdata follows pidx one clock later, long before the next tx_go
                if (tx_go) begin
                    pidx <= pidx + 1'b1;
                    bleft <= bleft - 16'd1;
                    if (bleft == 16'd1) st <= S_IDLE;
                end
        endcase
    end

    // LEDs: PCLK alive, the IP's interrupt, a command in progress, the throttles.
    reg [22:0] pclk_div = 23'd0;
    always @(posedge pclk) pclk_div <= pclk_div + 23'd1;
    assign led = {{(5-WINDOWS){1'b0}}, throttle, st != S_IDLE, irq, pclk_div[22]};
endmodule

`default_nettype wire
