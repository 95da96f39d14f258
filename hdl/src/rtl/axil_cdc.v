// axil_cdc: an AXI4-Lite clock-domain crossing, for window_unit_axis's register port when the
// processor's bus runs on its own clock (an SoC's system clock) and the IP on the pixel clock.
// The slave side (s_axil_*) is on s_aclk, the master side (m_axil_*, to window_unit_axis's
// s_axil_*) on m_aclk; the two clocks may be unrelated.
//
// One access at a time in each direction (a write and a read may be in flight together), as
// bundled data under a toggle handshake: the slave side takes the access into registers, then
// flips a request level; the level crosses through two flip-flops (async_reg) and the master
// side performs the access with the registers, which do not change until the acknowledge level,
// flipped with the response in registers, has crossed back the same way. So no bit is used on
// the other side while it changes. A write costs about 2 clocks of each side plus the two
// synchronisers each way (about 6 + 6 clocks in all); reads the same. Responses (bresp, rresp,
// rdata) are the IP's. Resets are synchronous and active low, one per side; assert both
// together (and hold each for 3 clocks of its side) so that the toggles start equal.
// docs/window-logic.md, "The register port on its own clock".
`timescale 1ns / 1ps
`default_nettype none

module axil_cdc #(
    parameter integer ADDR_BITS = 12    // address width (window_unit_axis: 12)
) (
    input  wire                 s_aclk,          // the processor's bus clock
    input  wire                 s_aresetn,       // synchronous to s_aclk, active low
    input  wire [ADDR_BITS-1:0] s_axil_awaddr,   // from the processor's bus
    input  wire                 s_axil_awvalid,
    output wire                 s_axil_awready,
    input  wire [31:0]          s_axil_wdata,
    input  wire [3:0]           s_axil_wstrb,
    input  wire                 s_axil_wvalid,
    output wire                 s_axil_wready,
    output wire [1:0]           s_axil_bresp,
    output wire                 s_axil_bvalid,
    input  wire                 s_axil_bready,
    input  wire [ADDR_BITS-1:0] s_axil_araddr,
    input  wire                 s_axil_arvalid,
    output wire                 s_axil_arready,
    output wire [31:0]          s_axil_rdata,
    output wire [1:0]           s_axil_rresp,
    output wire                 s_axil_rvalid,
    input  wire                 s_axil_rready,
    input  wire                 m_aclk,          // the IP's clock (window_unit_axis's aclk)
    input  wire                 m_aresetn,       // synchronous to m_aclk, active low
    output wire [ADDR_BITS-1:0] m_axil_awaddr,   // to window_unit_axis
    output wire                 m_axil_awvalid,
    input  wire                 m_axil_awready,
    output wire [31:0]          m_axil_wdata,
    output wire [3:0]           m_axil_wstrb,
    output wire                 m_axil_wvalid,
    input  wire                 m_axil_wready,
    input  wire [1:0]           m_axil_bresp,
    input  wire                 m_axil_bvalid,
    output wire                 m_axil_bready,
    output wire [ADDR_BITS-1:0] m_axil_araddr,
    output wire                 m_axil_arvalid,
    input  wire                 m_axil_arready,
    input  wire [31:0]          m_axil_rdata,
    input  wire [1:0]           m_axil_rresp,
    input  wire                 m_axil_rvalid,
    output wire                 m_axil_rready
);
    // ---------------------------------------------------------------------------------------
    // Slave side (s_aclk): take an access, flip its request, wait for the acknowledge.
    // ---------------------------------------------------------------------------------------
    reg [ADDR_BITS-1:0] w_addr = {ADDR_BITS{1'b0}};  // bundled with w_req
    reg [31:0]          w_data = 32'd0;
    reg [3:0]           w_strb = 4'd0;
    reg                 w_req = 1'b0;     // flips when a write is handed over
    reg                 w_busy = 1'b0;    // a write is across, or its response not yet taken
    reg                 b_valid = 1'b0;
    reg [ADDR_BITS-1:0] r_addr = {ADDR_BITS{1'b0}};  // bundled with r_req
    reg                 r_req = 1'b0;
    reg                 r_busy = 1'b0;
    reg                 r_valid = 1'b0;
    (* async_reg = "true" *) reg [1:0] w_ack_s = 2'b00;  // m side's w_ack, synchronised
    (* async_reg = "true" *) reg [1:0] r_ack_s = 2'b00;
    reg                 w_ack_seen = 1'b0;  // the last acknowledge level acted on
    reg                 r_ack_seen = 1'b0;
    // Master side's registers, declared here since the slave side reads them: the acknowledge
    // levels and the responses bundled with them.
    reg                 w_ack = 1'b0;     // flips when the write's response is in b_resp_m
    reg                 r_ack = 1'b0;     // flips when the read's response is in r_data_m, r_resp_m
    reg [1:0]           b_resp_m = 2'b00;
    reg [1:0]           r_resp_m = 2'b00;
    reg [31:0]          r_data_m = 32'd0;

    wire s_wr = s_axil_awvalid & s_axil_wvalid & ~w_busy;
    wire s_rd = s_axil_arvalid & ~r_busy;
    wire w_done = w_ack_s[1] != w_ack_seen;   // the acknowledge came back: response ready
    wire r_done = r_ack_s[1] != r_ack_seen;

    always @(posedge s_aclk) begin
        w_ack_s <= {w_ack_s[0], w_ack};
        r_ack_s <= {r_ack_s[0], r_ack};
        if (~s_aresetn) begin
            w_req <= 1'b0; w_busy <= 1'b0; b_valid <= 1'b0; w_ack_seen <= 1'b0;
            r_req <= 1'b0; r_busy <= 1'b0; r_valid <= 1'b0; r_ack_seen <= 1'b0;
            w_ack_s <= 2'b00; r_ack_s <= 2'b00;
        end else begin
            if (s_wr) begin
                w_addr <= s_axil_awaddr; w_data <= s_axil_wdata; w_strb <= s_axil_wstrb;
                w_busy <= 1'b1;
            end
            // The request flips the clock after the bundle was registered, so it is stable first.
            if (w_busy & ~b_valid & (w_req == w_ack_seen) & ~w_done) w_req <= ~w_req;
            if (w_done) begin w_ack_seen <= w_ack_s[1]; b_valid <= 1'b1; end
            if (b_valid & s_axil_bready) begin b_valid <= 1'b0; w_busy <= 1'b0; end

            if (s_rd) begin r_addr <= s_axil_araddr; r_busy <= 1'b1; end
            if (r_busy & ~r_valid & (r_req == r_ack_seen) & ~r_done) r_req <= ~r_req;
            if (r_done) begin r_ack_seen <= r_ack_s[1]; r_valid <= 1'b1; end
            if (r_valid & s_axil_rready) begin r_valid <= 1'b0; r_busy <= 1'b0; end
        end
    end

    assign s_axil_awready = s_wr;
    assign s_axil_wready = s_wr;
    assign s_axil_bvalid = b_valid;
    assign s_axil_bresp = b_resp_m;      // stable from before the acknowledge to the next write
    assign s_axil_arready = s_rd;
    assign s_axil_rvalid = r_valid;
    assign s_axil_rdata = r_data_m;      // the same for the read response
    assign s_axil_rresp = r_resp_m;

    // ---------------------------------------------------------------------------------------
    // Master side (m_aclk): on a new request level, perform the access, then acknowledge.
    // ---------------------------------------------------------------------------------------
    (* async_reg = "true" *) reg [1:0] w_req_s = 2'b00;
    (* async_reg = "true" *) reg [1:0] r_req_s = 2'b00;
    reg aw_pend = 1'b0, wd_pend = 1'b0, b_wait = 1'b0;  // the write's address, data, response due
    reg ar_pend = 1'b0, rd_wait = 1'b0;                 // the read's address, data due

    wire w_new = (w_req_s[1] != w_ack) & ~aw_pend & ~wd_pend & ~b_wait;
    wire r_new = (r_req_s[1] != r_ack) & ~ar_pend & ~rd_wait;

    always @(posedge m_aclk) begin
        w_req_s <= {w_req_s[0], w_req};
        r_req_s <= {r_req_s[0], r_req};
        if (~m_aresetn) begin
            w_ack <= 1'b0; aw_pend <= 1'b0; wd_pend <= 1'b0; b_wait <= 1'b0;
            r_ack <= 1'b0; ar_pend <= 1'b0; rd_wait <= 1'b0;
            w_req_s <= 2'b00; r_req_s <= 2'b00;
        end else begin
            if (w_new) begin aw_pend <= 1'b1; wd_pend <= 1'b1; b_wait <= 1'b1; end
            if (aw_pend & m_axil_awready) aw_pend <= 1'b0;
            if (wd_pend & m_axil_wready) wd_pend <= 1'b0;
            if (b_wait & ~aw_pend & ~wd_pend & m_axil_bvalid) begin
                b_resp_m <= m_axil_bresp; b_wait <= 1'b0; w_ack <= ~w_ack;
            end

            if (r_new) begin ar_pend <= 1'b1; rd_wait <= 1'b1; end
            if (ar_pend & m_axil_arready) ar_pend <= 1'b0;
            if (rd_wait & ~ar_pend & m_axil_rvalid) begin
                r_data_m <= m_axil_rdata; r_resp_m <= m_axil_rresp; rd_wait <= 1'b0; r_ack <= ~r_ack;
            end
        end
    end

    assign m_axil_awaddr = w_addr;
    assign m_axil_awvalid = aw_pend;
    assign m_axil_wdata = w_data;
    assign m_axil_wstrb = w_strb;
    assign m_axil_wvalid = wd_pend;
    assign m_axil_bready = b_wait & ~aw_pend & ~wd_pend;
    assign m_axil_araddr = r_addr;
    assign m_axil_arvalid = ar_pend;
    assign m_axil_rready = rd_wait & ~ar_pend;
endmodule

`default_nettype wire
