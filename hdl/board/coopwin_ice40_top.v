// coopwin_ice40_top: the window unit on a Lattice iCE40-HX8K breakout board (ct256), between
// an OV7670-style DVP camera and a host PC on the board's FT2232H UART (channel B).
// Board, pinout, protocol and build: docs/board.md. Build: scripts/board-fpga.sh.
// Synthesised, placed, routed and packed only: NOT run on hardware.
//
// Two clock domains:
//   clk12     the board's 12 MHz oscillator: UART, host command parser, SCCB writer,
//             capture-buffer read side, XCLK for the camera.
//   cam_pclk  the camera's pixel clock: the camera inputs, the pixel formatter, the
//             window_unit (its whole contract is on the pixel clock) and the capture FSM,
//             capture-buffer write side.
// Nothing crosses between them except through the three handshakes marked CDC below
// (coordinate bytes, window result, reset) and the dual-clock capture buffer. Each is
// "bundled data": a multi-bit bus is made stable in the sending domain first, then one
// level (request/done) crosses through two flip-flops, and the bus is not changed again
// until the acknowledge comes back through two flip-flops. The receiver reads the bus only
// after it has seen the synchronised level, so no bus bit is ever sampled while it moves.
//
// Host protocol (all multi-byte fields big-endian):
//   host -> board  'W' flags xmin_hi xmin_lo xmax_hi xmax_lo ymin_hi ymin_lo ymax_hi ymax_lo
//                  flags[0] decimate, flags[2:1] pixel mode (0 raw 8-bit, 1 RGB565,
//                  2 YUV422 luma; 3 is taken as raw)
//                  'S' reg value: one SCCB write to the camera (device id 0x42)
//                  Any other byte, and any byte while a command is in progress, is dropped.
//   board -> host  'C' 'W' type b3 b4 cnt[23:16] cnt[15:8] cnt[7:0] n[15:8] n[7:0]
//                  payload (n pixels, raster order; 1 byte each, or 2 bytes high first in
//                  RGB565), then one byte: XOR of every byte from `type` to the payload's end.
//                  type 0x00 window, 0x01 set refused (coord_error), 0x02 window larger
//                  than the buffer (first 2**BUF_AW pixels sent), 0x03 timeout (no pixel
//                  clock or no frame; the pixel-clock domain is reset), 0x10 SCCB write done.
//                  For windows b3 = flags, b4 = frame number (mod 256, counted from
//                  configuration); for SCCB b3 = reg, b4 = value. cnt is the number of
//                  pixels the unit delivered, n the number sent.
`default_nettype none

module coopwin_ice40_top #(
    parameter integer WIDTH = 640,          // VGA: coordinates are 8 bytes (high byte first)
    parameter integer HEIGHT = 480,
    parameter integer BUF_AW = 12,          // capture buffer 2**12 pixels x 16 bits = 16 of the 32 BRAMs
    parameter integer CLKS_PER_BIT = 4,     // 12 MHz / 4 = 3 Mbaud (exact on the FT2232H)
    parameter integer SCCB_QUARTER = 30,    // 12 MHz / (4 * 30) = 100 kHz SIOC
    parameter integer TIMEOUT_LOG2 = 24,    // 2**24 / 12 MHz = 1.4 s without a frame: timeout
    parameter [0:0]   VSYNC_ACTIVE_HIGH = 1'b1  // OV7670 default (COM10[1] = 0): fval = ~VSYNC
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
    localparam [1:0] MODE_RAW = 2'd0, MODE_RGB565 = 2'd1, MODE_YUV = 2'd2;
    localparam [0:0] WIDE = (WIDTH > 256) || (HEIGHT > 256);   // as in window_unit
    localparam [2:0] LAST_BYTE = WIDE ? 3'd7 : 3'd3;
    localparam integer DEPTH = 1 << BUF_AW;
    localparam [15:0] DEPTH16 = 16'd1 << BUF_AW;
    localparam integer TW = TIMEOUT_LOG2 + 1;

    // The two clocks enter on global-buffer pins (J3, H16) and go straight onto the global
    // network through the pads' own buffers (SB_GB_IO), so neither clock passes through the
    // fabric (nextpnr would otherwise route pad -> fabric -> SB_GB). Simulation: plain wires.
    wire clk;                       // 12 MHz
    wire pclk;                      // pixel clock
    // XCLK (the OV7670 accepts 10..48 MHz) is the 12 MHz forwarded through a DDR output
    // register (1 on the rising edge, 0 on the falling), the usual way to send a clock out.
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

    // =======================================================================================
    // Signals that cross (each one named once here; the crossings are marked CDC).
    // =======================================================================================
    // clk12 -> pclk, coordinate bytes: c_data/c_last/c_dec/c_mode bundled with c_req.
    reg        c_req = 1'b0;
    reg  [7:0] c_data = 8'd0;
    reg        c_last = 1'b0;       // this byte completes a set
    reg        c_dec = 1'b0;        // decimate for the set (window_unit samples it per byte)
    reg  [1:0] c_mode = 2'd0;       // pixel mode for the set's frame
    // pclk -> clk12, window result: p_refused/p_count/p_frame bundled with p_done.
    reg        p_done = 1'b0;
    reg        p_refused = 1'b0;
    reg [23:0] p_count = 24'd0;
    reg  [7:0] p_frame = 8'd0;
    reg        done_ack = 1'b0;     // clk12 -> pclk: the result has been read
    // clk12 -> pclk reset request, acknowledged by the reset itself.
    reg        rst_req = 1'b0;

    // =======================================================================================
    // Pixel-clock domain
    // =======================================================================================
    wire coord_ready;               // window_unit's CRDY1
    wire coord_error;
    wire pixel_strobe;
    wire [15:0] pixel_out;

    // CDC: the clk12 levels, two flip-flops each.
    wire c_req_p, done_ack_p, p_rst;
    coopwin_sync2 sync_req (.clk(pclk), .d(c_req), .q(c_req_p));
    coopwin_sync2 sync_ack (.clk(pclk), .d(done_ack), .q(done_ack_p));
    coopwin_sync2 sync_rst (.clk(pclk), .d(rst_req), .q(p_rst));

    // Camera inputs, registered on PCLK's rising edge (the OV7670 changes D, HREF and VSYNC
    // on the falling edge by default, COM10[4] = 0). fv0 is frame valid: the OV7670's VSYNC
    // pulses high between frames, so it is VSYNC inverted (VSYNC_ACTIVE_HIGH = 1; set 0 for a
    // sensor whose VSYNC is low between frames, e.g. an OV7670 with COM10[1] = 1). It is high through the
    // vertical blanking lines too, which is harmless: the unit counts lines by lval pulses.
    // Inverted before the flip-flop so that it powers up as "between frames".
    reg       fv0 = 1'b0, hr0 = 1'b0;
    reg [7:0] d0 = 8'd0;
    always @(posedge pclk) begin
        fv0 <= VSYNC_ACTIVE_HIGH ? ~cam_vsync : cam_vsync;
        hr0 <= cam_href;
        d0 <= cam_d;
    end

    // Pixel formatter: the camera's bytes become the unit's fval/lval/pixel/pixel_valid.
    // fval = fv0, lval = HREF. Raw 8-bit: every byte of HREF is a pixel.
    // RGB565 / YUV422: two bytes per pixel; `phase` is 0 on a pair's first byte (reset by
    // HREF low, so each line starts on a first byte) and pixel_valid is raised with the
    // second, carrying {first, second} (RGB565, R5G3 then G3B5) or the first byte alone
    // (YUYV order: the luma byte).
    reg [1:0]  mode_p = MODE_RAW;   // taken from c_mode when a set completes
    reg        phase = 1'b0;
    reg  [7:0] first = 8'd0;
    reg        fval1 = 1'b0, lval1 = 1'b0, pv1 = 1'b0;
    reg [15:0] pix1 = 16'd0;
    always @(posedge pclk) begin
        fval1 <= fv0;
        lval1 <= hr0;
        phase <= hr0 & ~phase;
        if (~phase) first <= d0;
        case (mode_p)
            MODE_RGB565: begin pix1 <= {first, d0};       pv1 <= phase; end
            MODE_YUV:    begin pix1 <= {8'd0, first};     pv1 <= phase; end
            default:     begin pix1 <= {8'd0, d0};        pv1 <= 1'b1;  end
        endcase
    end

    window_unit #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .PIXEL_BITS(16)) u_window (
        .clock(pclk),
        .fval(fval1),
        .lval(lval1),
        .pixel(pix1),
        .coord_strobe(c_req_p),     // the synchronised request is the strobe ...
        .coord_data(c_data),        // ... and the bundled byte, stable while it is high
        .coord_ready(coord_ready),
        .decimate(c_dec),           // bundled too
        .pixel_strobe(pixel_strobe),
        .pixel_out(pixel_out),
        .coord_error(coord_error),
        .pixel_valid(pv1),
        .reset(p_rst),
        .armed(),
        .window_done(),
        .set_accepted()
    );

    // Capture FSM. The unit has no "window armed" or "window done" output, so this mirrors
    // the contract: a valid set whose last byte is taken on edge e0 (the edge the unit raises
    // coord_ready) arms the first frame whose fval the unit first samples high on edge e0+1
    // or later. This FSM sees coord_ready's rising edge at e0+1 (set_done), and with it
    // fval_rise if that frame starts on e0+1 (`rose_now`); it reads coord_error at e0+2 (the
    // unit updates it at e0+1), and from e0+2 on takes the first edge on which fval1 is high
    // after being low. fval_rise at edge k is fval1 high before k and low before k-1: the
    // edge the unit first samples fval high. A frame starting on e0 or earlier is not the
    // set's (the unit arms the next one), and the FSM, still idle at e0, ignores it.
    // The window is complete when that frame's fval falls: the unit strobes no pixel once it
    // samples fval low, so its last strobe is registered on that edge; FLUSH waits 4 clocks.
    localparam [2:0] P_IDLE = 3'd0, P_CHECK = 3'd1, P_ARMED = 3'd2, P_CAPTURE = 3'd3,
                     P_FLUSH = 3'd4, P_DONE = 3'd5;
    reg  [2:0] pst = P_IDLE;
    reg        ready_q = 1'b0;
    reg        fval_q = 1'b0;       // fval1 one clock later (the unit's FVC)
    reg        rose_now = 1'b0;     // the unit first saw fval high on the edge after the set (e0+1)
    reg  [1:0] flush = 2'd0;
    reg  [7:0] frame_cnt = 8'd0;    // fval rising edges since configuration (never reset)
    wire fval_rise = fval1 & ~fval_q;
    wire fval_fall = ~fval1 & fval_q;
    wire set_done = coord_ready & ~ready_q & c_last;   // c_last is bundled with c_req
    wire capturing = (pst == P_CAPTURE) | (pst == P_FLUSH);
    wire buf_we = capturing & pixel_strobe & ~|p_count[23:BUF_AW];

    always @(posedge pclk) begin
        fval_q <= fval1;
        frame_cnt <= frame_cnt + {7'd0, fval_rise};
    end

    always @(posedge pclk) begin
        if (p_rst) begin
            pst <= P_IDLE; ready_q <= 1'b0; p_done <= 1'b0; p_refused <= 1'b0;
            p_count <= 24'd0; mode_p <= MODE_RAW; flush <= 2'd0; rose_now <= 1'b0;
        end else begin
            ready_q <= coord_ready;
            if (capturing & pixel_strobe & ~&p_count) p_count <= p_count + 24'd1;
            case (pst)
                P_IDLE:
                    if (set_done) begin
                        pst <= P_CHECK; mode_p <= c_mode; p_count <= 24'd0; p_refused <= 1'b0;
                        // a frame starting now (e0+1) is the set's; its number is counted now
                        rose_now <= fval_rise; p_frame <= frame_cnt;
                    end
                P_CHECK:
                    if (coord_error) begin
                        pst <= P_DONE; p_refused <= 1'b1; p_done <= 1'b1;
                    end else if (rose_now) begin
                        pst <= fval_fall ? P_FLUSH : P_CAPTURE; flush <= 2'd0;
                    end else if (fval_rise) begin
                        pst <= P_CAPTURE; p_frame <= frame_cnt;
                    end else
                        pst <= P_ARMED;
                P_ARMED:
                    if (fval_rise) begin pst <= P_CAPTURE; p_frame <= frame_cnt; end
                P_CAPTURE:
                    if (fval_fall) begin pst <= P_FLUSH; flush <= 2'd0; end
                P_FLUSH: begin
                    flush <= flush + 2'd1;
                    if (&flush) begin pst <= P_DONE; p_done <= 1'b1; end
                end
                default:  // P_DONE: held until clk12 has read the result and the buffer
                    if (done_ack_p) begin pst <= P_IDLE; p_done <= 1'b0; end
            endcase
        end
    end

    // Capture buffer: written on PCLK, read on clk12 (SB_RAM40_4K has separate write and
    // read clocks). The read side reads only after p_done has crossed, and the write side
    // writes only while capturing, before p_done rises: never both at once.
    reg [15:0] buf_mem [0:DEPTH-1];
    reg [15:0] buf_rdata;
    wire [BUF_AW-1:0] buf_raddr;
    always @(posedge pclk)
        if (buf_we) buf_mem[p_count[BUF_AW-1:0]] <= pixel_out;
    always @(posedge clk)
        buf_rdata <= buf_mem[buf_raddr];

    // =======================================================================================
    // 12 MHz domain
    // =======================================================================================
    // CDC: the pixel-clock levels, two flip-flops each.
    wire c_ack, p_done_12, rst_ack;
    coopwin_sync2 sync_cack (.clk(clk), .d(coord_ready), .q(c_ack));
    coopwin_sync2 sync_done (.clk(clk), .d(p_done), .q(p_done_12));
    coopwin_sync2 sync_rack (.clk(clk), .d(p_rst), .q(rst_ack));

    wire       rx_valid;
    wire [7:0] rx_data;
    coopwin_uart_rx #(.CLKS_PER_BIT(CLKS_PER_BIT)) u_rx (
        .clk(clk), .rx(uart_rx), .valid(rx_valid), .data(rx_data));

    reg        tx_valid;
    reg  [7:0] tx_data;
    wire       tx_ready;
    coopwin_uart_tx #(.CLKS_PER_BIT(CLKS_PER_BIT)) u_tx (
        .clk(clk), .valid(tx_valid), .data(tx_data), .ready(tx_ready), .tx(uart_tx));
    wire tx_go = tx_valid & tx_ready;   // a byte is handed to the transmitter this clock

    reg        sccb_start = 1'b0;
    reg  [7:0] s_reg = 8'd0, s_val = 8'd0;
    wire       sccb_done;
    coopwin_sccb_write #(.QUARTER(SCCB_QUARTER)) u_sccb (
        .clk(clk), .start(sccb_start), .reg_addr(s_reg), .value(s_val),
        .done(sccb_done), .sioc(cam_sioc), .siod(cam_siod));

    // Reset request for the pixel-clock domain (after a timeout): held until the reset is
    // seen back, so it takes effect even if PCLK was stopped when it was raised.
    reg rst_start = 1'b0;
    always @(posedge clk)
        if (rst_start) rst_req <= 1'b1;
        else if (rst_ack) rst_req <= 1'b0;
    wire rst_pending = rst_req | rst_ack;

    localparam [3:0] S_IDLE = 4'd0, S_WARG = 4'd1, S_SARG = 4'd2, S_SEND = 4'd3,
                     S_WAIT = 4'd4, S_SCCB = 4'd5, S_HDR = 4'd6, S_PAY = 4'd7,
                     S_CHK = 4'd8, S_RELEASE = 4'd9;
    reg  [3:0] st = S_IDLE;
    reg  [3:0] argn = 4'd0;         // argument bytes received
    reg  [7:0] flags = 8'd0;
    reg [63:0] coords = 64'd0;      // xmin, xmax, ymin, ymax: 16 bits each, high byte first
    reg  [2:0] bidx = 3'd0;         // coordinate byte being forwarded
    reg  [1:0] hs = 2'd0;           // handshake phase for that byte
    reg [TW-1:0] timer = {TW{1'b0}};
    reg  [7:0] ftype = 8'd0, b3 = 8'd0, b4 = 8'd0, chk = 8'd0;
    reg [23:0] cnt = 24'd0;
    reg [15:0] nsend = 16'd0;
    reg  [3:0] hidx = 4'd0;
    reg [BUF_AW:0] pidx = {(BUF_AW+1){1'b0}};
    reg        phi = 1'b0;          // RGB565: the next payload byte is a pixel's high byte
    reg        window_frame = 1'b0; // the frame reports a window: release the pclk FSM after
    reg        timed_out = 1'b0;    // sticky, for an LED

    assign buf_raddr = pidx[BUF_AW-1:0];
    wire rgb = flags[2:1] == MODE_RGB565;

    // The byte forwarded to the unit: WIDE units take all 8 bytes; narrow ones (<= 256) take
    // the low bytes, and a set with a non-zero high byte is sent as 0,0,0,0, which the unit
    // refuses (xmin < xmax fails), so the host gets "refused" as for any invalid set.
    wire hi_nonzero = |{coords[63:56], coords[47:40], coords[31:24], coords[15:8]};
    wire [2:0] wsel = WIDE ? bidx : {bidx[1:0], 1'b1};
    wire [7:0] fwd_byte = (~WIDE & hi_nonzero) ? 8'd0 : coords[63 - 8*wsel -: 8];

    // Frame header, byte by byte.
    reg [7:0] hdr_byte;
    always @* begin
        case (hidx)
            4'd0: hdr_byte = 8'h43;  // 'C'
            4'd1: hdr_byte = 8'h57;  // 'W'
            4'd2: hdr_byte = ftype;
            4'd3: hdr_byte = b3;
            4'd4: hdr_byte = b4;
            4'd5: hdr_byte = cnt[23:16];
            4'd6: hdr_byte = cnt[15:8];
            4'd7: hdr_byte = cnt[7:0];
            4'd8: hdr_byte = nsend[15:8];
            default: hdr_byte = nsend[7:0];
        endcase
    end
    wire [7:0] pay_byte = (rgb & phi) ? buf_rdata[15:8] : buf_rdata[7:0];

    always @* begin
        tx_valid = 1'b0;
        tx_data = hdr_byte;
        case (st)
            S_HDR: begin tx_valid = 1'b1; tx_data = hdr_byte; end
            S_PAY: begin tx_valid = 1'b1; tx_data = pay_byte; end
            S_CHK: begin tx_valid = 1'b1; tx_data = chk; end
            default: ;
        endcase
    end

    wire timeout = timer[TW-1];

    always @(posedge clk) begin
        sccb_start <= 1'b0;
        rst_start <= 1'b0;
        case (st)
            S_IDLE: begin
                argn <= 4'd0;
                if (rx_valid) begin
                    if (rx_data == 8'h57) st <= S_WARG;        // 'W'
                    else if (rx_data == 8'h53) st <= S_SARG;   // 'S'
                end
            end
            S_WARG:
                if (rx_valid) begin
                    argn <= argn + 4'd1;
                    if (argn == 4'd0) flags <= rx_data;
                    else coords <= {coords[55:0], rx_data};
                    if (argn == 4'd8) begin
                        st <= S_SEND; bidx <= 3'd0; hs <= 2'd0; timer <= {TW{1'b0}};
                    end
                end
            S_SARG:
                if (rx_valid) begin
                    argn <= argn + 4'd1;
                    if (argn == 4'd0) s_reg <= rx_data;
                    else begin s_val <= rx_data; sccb_start <= 1'b1; st <= S_SCCB; end
                end
            S_SCCB:
                if (sccb_done) begin
                    ftype <= 8'h10; b3 <= s_reg; b4 <= s_val; cnt <= 24'd0; nsend <= 16'd0;
                    window_frame <= 1'b0; st <= S_HDR; hidx <= 4'd0; chk <= 8'd0;
                end
            S_SEND: begin
                // CDC: one coordinate byte per four-phase handshake. The byte (and c_last,
                // c_dec, c_mode) is set one clk12 clock before c_req rises and held until
                // coord_ready has been seen high and then low again through two flip-flops.
                // The unit's own handshake is four-phase, so c_req, synchronised, is its
                // coord_strobe and coord_ready, synchronised, is the acknowledge.
                timer <= timer + {{(TW-1){1'b0}}, 1'b1};
                if (~timeout & ~rst_pending) begin  // (a timeout is handled below)
                    case (hs)
                        2'd0: begin
                            c_data <= fwd_byte; c_last <= bidx == LAST_BYTE;
                            c_dec <= flags[0]; c_mode <= flags[2:1]; hs <= 2'd1;
                        end
                        2'd1: begin c_req <= 1'b1; hs <= 2'd2; end
                        2'd2: if (c_ack) begin c_req <= 1'b0; hs <= 2'd3; end
                        default:
                            if (~c_ack) begin
                                hs <= 2'd0; bidx <= bidx + 3'd1;
                                if (bidx == LAST_BYTE) st <= S_WAIT;
                            end
                    endcase
                end
            end
            S_WAIT: begin
                timer <= timer + {{(TW-1){1'b0}}, 1'b1};
                if (p_done_12) begin
                    // CDC: p_refused/p_count/p_frame were set when p_done rose and stay put
                    // until done_ack is seen in the pixel-clock domain.
                    ftype <= p_refused ? 8'h01 : (|p_count[23:BUF_AW] & (p_count != {8'd0, DEPTH16})) ? 8'h02 : 8'h00;
                    cnt <= p_refused ? 24'd0 : p_count;
                    nsend <= p_refused ? 16'd0 : (|p_count[23:BUF_AW]) ? DEPTH16 : p_count[15:0];
                    b3 <= flags; b4 <= p_frame;
                    window_frame <= 1'b1; st <= S_HDR; hidx <= 4'd0; chk <= 8'd0;
                end
            end
            S_HDR:
                if (tx_go) begin
                    if (hidx >= 4'd2) chk <= chk ^ hdr_byte;
                    hidx <= hidx + 4'd1;
                    if (hidx == 4'd9) begin
                        pidx <= {(BUF_AW+1){1'b0}}; phi <= rgb;
                        st <= (nsend != 16'd0) ? S_PAY : S_CHK;
                    end
                end
            S_PAY:
                // buf_rdata follows pidx one clock later; the transmitter is busy for
                // 10 bits after each byte, so it is always settled before the next tx_go.
                if (tx_go) begin
                    chk <= chk ^ pay_byte;
                    if (rgb & phi) phi <= 1'b0;
                    else begin
                        phi <= rgb;
                        pidx <= pidx + 1'b1;
                        if ({{(15-BUF_AW){1'b0}}, pidx} == nsend - 16'd1) st <= S_CHK;
                    end
                end
            S_CHK:
                if (tx_go) begin
                    timer <= {TW{1'b0}};
                    st <= window_frame ? S_RELEASE : S_IDLE;
                end
            S_RELEASE: begin
                // CDC: done_ack until p_done is seen low (the pclk FSM is back to idle).
                timer <= timer + {{(TW-1){1'b0}}, 1'b1};
                done_ack <= 1'b1;
                if ((done_ack & ~p_done_12) | timeout) begin
                    done_ack <= 1'b0; st <= S_IDLE;
                    if (timeout) begin rst_start <= 1'b1; timed_out <= 1'b1; end
                end
            end
            default: st <= S_IDLE;
        endcase
        // Timeout while forwarding or waiting for a frame: report it and reset the pixel-clock
        // domain (the unit may hold part of a set; only its reset clears the byte index).
        if ((st == S_SEND || st == S_WAIT) && timeout) begin
            c_req <= 1'b0; rst_start <= 1'b1; timed_out <= 1'b1;
            ftype <= 8'h03; b3 <= flags; b4 <= 8'd0; cnt <= 24'd0; nsend <= 16'd0;
            window_frame <= 1'b0; st <= S_HDR; hidx <= 4'd0; chk <= 8'd0;
        end
    end

    // LEDs (D2..D9): PCLK alive, frames, coord_error, busy, timeout seen, mode, decimate.
    reg [22:0] pclk_div = 23'd0;
    always @(posedge pclk) pclk_div <= pclk_div + 23'd1;
    assign led = {c_dec, mode_p, timed_out, st != S_IDLE, coord_error, frame_cnt[3], pclk_div[22]};
endmodule

// Two-flip-flop synchroniser for one level.
module coopwin_sync2 (
    input  wire clk,
    input  wire d,
    output wire q
);
    (* async_reg = "true" *) reg s1 = 1'b0;
    (* async_reg = "true" *) reg s2 = 1'b0;
    always @(posedge clk) begin
        s1 <= d;
        s2 <= s1;
    end
    assign q = s2;
endmodule

// UART receiver, 8N1, CLKS_PER_BIT clocks a bit (>= 4). The line is kept inverted in the
// flip-flops (idle = 0) so that every register powers up at 0 as the iCE40's do.
module coopwin_uart_rx #(
    parameter integer CLKS_PER_BIT = 4
) (
    input  wire       clk,
    input  wire       rx,
    output reg        valid = 1'b0,  // one clock per byte received
    output reg  [7:0] data = 8'd0
);
    localparam integer CW = $clog2(CLKS_PER_BIT + 1);
    localparam integer BIT_M1 = CLKS_PER_BIT - 1;
    localparam integer HALF_M1 = CLKS_PER_BIT / 2 - 1;
    (* async_reg = "true" *) reg n1 = 1'b0;
    (* async_reg = "true" *) reg n2 = 1'b0;
    always @(posedge clk) begin n1 <= ~rx; n2 <= n1; end
    wire line = ~n2;

    localparam [1:0] IDLE = 2'd0, BITS = 2'd1, STOP_WAIT = 2'd2;
    reg [1:0]    state = IDLE;
    reg [CW-1:0] cnt = {CW{1'b0}};
    reg [3:0]    nbit = 4'd0;        // 0 start, 1..8 data, 9 stop
    reg [7:0]    sh = 8'd0;
    always @(posedge clk) begin
        valid <= 1'b0;
        case (state)
            IDLE:
                // The falling edge is seen 2-3 clocks late (the synchroniser); sampling
                // CLKS_PER_BIT/2 clocks later lands at 50..50+100/CLKS_PER_BIT % of the bit.
                if (~line) begin
                    state <= BITS; nbit <= 4'd0; cnt <= HALF_M1[CW-1:0];
                end
            BITS:
                if (cnt != 0) cnt <= cnt - 1'b1;
                else begin
                    cnt <= BIT_M1[CW-1:0];
                    nbit <= nbit + 4'd1;
                    if (nbit == 4'd0) begin
                        if (line) state <= IDLE;            // a glitch, not a start bit
                    end else if (nbit == 4'd9) begin
                        if (line) begin valid <= 1'b1; data <= sh; state <= IDLE; end
                        else state <= STOP_WAIT;            // framing error: drop the byte
                    end else
                        sh <= {line, sh[7:1]};              // LSB first
                end
            default:  // STOP_WAIT: wait for the line to go idle again
                if (line) state <= IDLE;
        endcase
    end
endmodule

// UART transmitter, 8N1; a byte is taken on a clock with valid & ready.
module coopwin_uart_tx #(
    parameter integer CLKS_PER_BIT = 4
) (
    input  wire       clk,
    input  wire       valid,
    input  wire [7:0] data,
    output wire       ready,
    output wire       tx
);
    localparam integer CW = $clog2(CLKS_PER_BIT + 1);
    localparam integer BIT_M1 = CLKS_PER_BIT - 1;
    reg [9:0]    sh_n = 10'd0;      // inverted: {stop, data, start}, 0 = idle line (high)
    reg [3:0]    left = 4'd0;       // bits still to send
    reg [CW-1:0] cnt = {CW{1'b0}};
    assign ready = left == 4'd0;
    assign tx = ~sh_n[0];
    always @(posedge clk) begin
        if (ready) begin
            if (valid) begin
                sh_n <= ~{1'b1, data, 1'b0}; left <= 4'd10; cnt <= BIT_M1[CW-1:0];
            end
        end else if (cnt != 0)
            cnt <= cnt - 1'b1;
        else begin
            cnt <= BIT_M1[CW-1:0];
            sh_n <= {1'b0, sh_n[9:1]};
            left <= left - 4'd1;
        end
    end
endmodule

// SCCB three-phase write (OV7670 device id 0x42): start, id, reg, value, stop; the ninth
// ("don't care") bit of each phase is released. Each step lasts QUARTER clocks, a bit is four
// steps: SIOC falls, SIOD changes, SIOC rises, hold. SIOD is only driven low (open drain).
module coopwin_sccb_write #(
    parameter integer QUARTER = 30
) (
    input  wire       clk,
    input  wire       start,
    input  wire [7:0] reg_addr,
    input  wire [7:0] value,
    output reg        done = 1'b0,  // one clock when the stop condition is complete
    output wire       sioc,
    inout  wire       siod
);
    localparam integer QW = $clog2(QUARTER + 1);
    localparam integer Q_M1 = QUARTER - 1;
    localparam [6:0] LAST_STEP = 7'd113;  // 2 start + 27 * 4 bits + 4 stop
    reg          busy = 1'b0;
    reg [6:0]    step = 7'd0;
    reg [QW-1:0] q = {QW{1'b0}};
    reg [26:0]   bits = 27'd0;
    reg          sioc_n = 1'b0;     // inverted so the idle (high) state is the power-up 0
    reg          pull = 1'b0;       // 1: SIOD driven low
    assign sioc = ~sioc_n;
    assign siod = pull ? 1'b0 : 1'bz;

    wire [1:0] bphase = step[1:0] + 2'd2;  // (step - 2) mod 4: the step within a bit
    always @(posedge clk) begin
        done <= 1'b0;
        if (~busy) begin
            if (start) begin
                busy <= 1'b1; step <= 7'd0; q <= {QW{1'b0}};
                bits <= {8'h42, 1'b1, reg_addr, 1'b1, value, 1'b1};
                pull <= 1'b1;                       // start: SIOD falls while SIOC is high
            end
        end else if (q != Q_M1[QW-1:0])
            q <= q + 1'b1;
        else begin
            q <= {QW{1'b0}};
            step <= step + 7'd1;
            if (step == 7'd1) sioc_n <= 1'b1;                  // SIOC low after the start
            else if (step >= 7'd2 && step < 7'd110) begin
                case (bphase)
                    2'd0: begin pull <= ~bits[26]; bits <= {bits[25:0], 1'b1}; end
                    2'd1: sioc_n <= 1'b0;                      // SIOC rises: bit sampled
                    2'd2: ;
                    default: sioc_n <= 1'b1;                   // SIOC falls
                endcase
            end else if (step == 7'd110) pull <= 1'b1;         // stop: SIOD low ...
            else if (step == 7'd111) sioc_n <= 1'b0;           // ... SIOC high ...
            else if (step == 7'd112) pull <= 1'b0;             // ... SIOD rises
            else if (step == LAST_STEP) begin busy <= 1'b0; done <= 1'b1; end
        end
    end
endmodule

`default_nettype wire
