`timescale 1ns/1ps
// axil_cdc_tb: a self-checking Icarus bench of axil_cdc (hdl/verilog/axil_cdc.v) in front of
// window_unit_axis (hdl/verilog/window_unit_axis.v, its defaults: 256x256, 4 windows, FIFO 32),
// the processor's bus on s_aclk and the IP on an unrelated m_aclk (periods S_PERIOD and
// M_PERIOD, in ns).
//
//   iverilog -g2012 -o tb.vvp -P axil_cdc_tb.S_PERIOD=3 -P axil_cdc_tb.M_PERIOD=10 \
//       hdl/verilog/tb/axil_cdc_tb.v hdl/verilog/axil_cdc.v hdl/verilog/window_unit_axis.v
//   vvp -n tb.vvp            (exit status 0 and "PASS axil_cdc" only if every check held)
//
// The reference is the register map (docs/window-logic.md): INFO and GEOMETRY read as the
// parameters give them, X and Y read back what was written, CTRL its two bits, IRQ_ENABLE its
// WINDOWS bits. The bench writes random values to random registers and reads random registers
// back, with a write and a read to two different registers in flight together, and random
// bready/rready delays; every read must equal the shadow of what was written, and a response
// offered and not yet taken must not change (the AXI rule).
`default_nettype none

module axil_cdc_tb #(
    parameter real S_PERIOD = 3.0,
    parameter real M_PERIOD = 10.0,
    parameter integer ACCESSES = 400,
    parameter integer SEED = 1
);
    reg s_aclk = 1'b0, m_aclk = 1'b0;
    always #(S_PERIOD / 2) s_aclk = ~s_aclk;
    always #(M_PERIOD / 2) m_aclk = ~m_aclk;
    reg s_aresetn = 1'b0, m_aresetn = 1'b0;

    reg  [11:0] awaddr = 12'd0, araddr = 12'd0;
    reg  [31:0] wdata = 32'd0;
    reg         awvalid = 1'b0, wvalid = 1'b0, bready = 1'b0, arvalid = 1'b0, rready = 1'b0;
    wire        awready, wready, bvalid, arready, rvalid;
    wire [1:0]  bresp, rresp;
    wire [31:0] rdata;

    wire [11:0] m_awaddr, m_araddr;
    wire [31:0] m_wdata, m_rdata;
    wire [3:0]  m_wstrb;
    wire [1:0]  m_bresp, m_rresp;
    wire        m_awvalid, m_awready, m_wvalid, m_wready, m_bvalid, m_bready;
    wire        m_arvalid, m_arready, m_rvalid, m_rready;

    axil_cdc cdc (
        .s_aclk(s_aclk), .s_aresetn(s_aresetn),
        .s_axil_awaddr(awaddr), .s_axil_awvalid(awvalid), .s_axil_awready(awready),
        .s_axil_wdata(wdata), .s_axil_wstrb(4'hF), .s_axil_wvalid(wvalid), .s_axil_wready(wready),
        .s_axil_bresp(bresp), .s_axil_bvalid(bvalid), .s_axil_bready(bready),
        .s_axil_araddr(araddr), .s_axil_arvalid(arvalid), .s_axil_arready(arready),
        .s_axil_rdata(rdata), .s_axil_rresp(rresp), .s_axil_rvalid(rvalid), .s_axil_rready(rready),
        .m_aclk(m_aclk), .m_aresetn(m_aresetn),
        .m_axil_awaddr(m_awaddr), .m_axil_awvalid(m_awvalid), .m_axil_awready(m_awready),
        .m_axil_wdata(m_wdata), .m_axil_wstrb(m_wstrb), .m_axil_wvalid(m_wvalid), .m_axil_wready(m_wready),
        .m_axil_bresp(m_bresp), .m_axil_bvalid(m_bvalid), .m_axil_bready(m_bready),
        .m_axil_araddr(m_araddr), .m_axil_arvalid(m_arvalid), .m_axil_arready(m_arready),
        .m_axil_rdata(m_rdata), .m_axil_rresp(m_rresp), .m_axil_rvalid(m_rvalid), .m_axil_rready(m_rready));

    wire [31:0] m_tdata;
    wire [3:0]  m_tvalid, m_tuser, m_tlast;
    wire        irq, s_tready;
    window_unit_axis ip (
        .aclk(m_aclk), .aresetn(m_aresetn),
        .s_axis_tdata(8'd0), .s_axis_tvalid(1'b0), .s_axis_tready(s_tready), .s_axis_tuser(1'b0), .s_axis_tlast(1'b0),
        .m_axis_tdata(m_tdata), .m_axis_tvalid(m_tvalid), .m_axis_tready(4'hF), .m_axis_tuser(m_tuser), .m_axis_tlast(m_tlast),
        .s_axil_awaddr(m_awaddr), .s_axil_awvalid(m_awvalid), .s_axil_awready(m_awready),
        .s_axil_wdata(m_wdata), .s_axil_wstrb(m_wstrb), .s_axil_wvalid(m_wvalid), .s_axil_wready(m_wready),
        .s_axil_bresp(m_bresp), .s_axil_bvalid(m_bvalid), .s_axil_bready(m_bready),
        .s_axil_araddr(m_araddr), .s_axil_arvalid(m_arvalid), .s_axil_arready(m_arready),
        .s_axil_rdata(m_rdata), .s_axil_rresp(m_rresp), .s_axil_rvalid(m_rvalid), .s_axil_rready(m_rready),
        .irq(irq));

    integer seed = SEED, errors = 0, writes = 0, reads = 0, overlapped = 0;
    // Shadow of the writable registers: X, Y, CTRL of windows 0..3 (index 3k + r), IRQ_ENABLE.
    reg [31:0] shadow [0:12];

    function [11:0] reg_addr(input integer i);  // i in 0..12: 3k + r, or 12 for IRQ_ENABLE
        reg_addr = i == 12 ? 12'h00C : 12'h020 * (i / 3 + 1) + 12'h004 * (i % 3);
    endfunction
    function [31:0] reads_as(input integer i, input [31:0] v);
        reads_as = i == 12 ? {28'd0, v[3:0]} : (i % 3 == 2 ? {30'd0, v[1:0]} : v);
    endfunction

    task automatic wait_s(input integer n);
        repeat (n) @(posedge s_aclk);
    endtask

    task automatic write(input [11:0] a, input [31:0] d);
        begin
            @(negedge s_aclk) begin awaddr = a; wdata = d; awvalid = 1'b1; wvalid = 1'b1; end
            @(posedge s_aclk); while (!(awready && wready)) @(posedge s_aclk);
            @(negedge s_aclk) begin awvalid = 1'b0; wvalid = 1'b0; end
            wait_s($unsigned($random(seed)) % 4);
            @(negedge s_aclk) bready = 1'b1;
            @(posedge s_aclk); while (!bvalid) @(posedge s_aclk);
            if (bresp !== 2'b00) begin errors = errors + 1; $display("FAIL axil_cdc: bresp %b for %h", bresp, a); end
            @(negedge s_aclk) bready = 1'b0;
            writes = writes + 1;
        end
    endtask

    task automatic read(input [11:0] a, output [31:0] d);
        begin
            @(negedge s_aclk) begin araddr = a; arvalid = 1'b1; end
            @(posedge s_aclk); while (!arready) @(posedge s_aclk);
            @(negedge s_aclk) arvalid = 1'b0;
            wait_s($unsigned($random(seed)) % 4);
            @(negedge s_aclk) rready = 1'b1;
            @(posedge s_aclk); while (!rvalid) @(posedge s_aclk);
            d = rdata;
            if (rresp !== 2'b00) begin errors = errors + 1; $display("FAIL axil_cdc: rresp %b for %h", rresp, a); end
            @(negedge s_aclk) rready = 1'b0;
            reads = reads + 1;
        end
    endtask

    task automatic expect_read(input integer i);
        reg [31:0] got;
        begin
            read(reg_addr(i), got);
            if (got !== reads_as(i, shadow[i])) begin
                errors = errors + 1;
                $display("FAIL axil_cdc: register %h read %h, expected %h", reg_addr(i), got, reads_as(i, shadow[i]));
            end
        end
    endtask

    // The AXI rule on the slave side: a response offered and not yet taken does not change.
    reg        held = 1'b0, b_held = 1'b0;
    reg [31:0] held_data = 32'd0;
    reg [1:0]  held_resp = 2'b00, held_bresp = 2'b00;
    always @(posedge s_aclk) begin
        if (held && (!rvalid || rdata !== held_data || rresp !== held_resp)) begin
            errors = errors + 1;
            $display("FAIL axil_cdc: read response changed while offered (%h to %h)", held_data, rdata);
        end
        if (b_held && (!bvalid || bresp !== held_bresp)) begin
            errors = errors + 1;
            $display("FAIL axil_cdc: write response changed while offered");
        end
        held <= rvalid && !rready; held_data <= rdata; held_resp <= rresp;
        b_held <= bvalid && !bready; held_bresp <= bresp;
    end

    integer n, i, j;
    reg [31:0] v, got;
    initial begin
        for (i = 0; i < 13; i = i + 1) shadow[i] = 32'd0;
        repeat (4) @(posedge m_aclk);
        repeat (4) @(posedge s_aclk);
        @(negedge m_aclk) m_aresetn = 1'b1;
        @(negedge s_aclk) s_aresetn = 1'b1;
        read(12'h000, got);
        if (got !== {16'd32, 16'd4}) begin errors = errors + 1; $display("FAIL axil_cdc: INFO %h", got); end
        read(12'h004, got);
        if (got !== {16'd256, 16'd256}) begin errors = errors + 1; $display("FAIL axil_cdc: GEOMETRY %h", got); end
        for (n = 0; n < ACCESSES; n = n + 1) begin
            i = $unsigned($random(seed)) % 13;
            j = $unsigned($random(seed)) % 13;
            v = $random(seed);
            if (i != j && ($unsigned($random(seed)) % 2)) begin
                // A write and a read of another register in flight together.
                fork
                    write(reg_addr(i), v);
                    expect_read(j);
                join
                overlapped = overlapped + 1;
                shadow[i] = v;
            end else begin
                write(reg_addr(i), v);
                shadow[i] = v;
                expect_read(j);
            end
            expect_read(i);
        end
        if (errors == 0 && overlapped > 0)
            $display("PASS axil_cdc S_PERIOD %0.1f M_PERIOD %0.1f: %0d writes, %0d reads (%0d overlapped with a write)",
                     S_PERIOD, M_PERIOD, writes, reads, overlapped);
        else $fatal(1, "FAIL axil_cdc: %0d errors", errors);
        $finish;
    end
endmodule

`default_nettype wire
