// The host PC's side of the board's UART (3 Mbaud 8N1), for the board testbenches
// (`include inside the testbench module, which declares host_tx, board_tx, BIT_NS and errors).
// host_send drives a byte; every byte the board sends is queued, and host_get takes the next
// one or fails the run after timeout_ns; fail counts an error and prints why.
    task host_send(input [7:0] b);
        integer k;
        begin
            host_tx = 1'b0; #(BIT_NS);
            for (k = 0; k < 8; k = k + 1) begin host_tx = b[k]; #(BIT_NS); end
            host_tx = 1'b1; #(BIT_NS);
        end
    endtask

    reg [7:0] rxq [0:65535];
    integer rx_w = 0, rx_r = 0, rx_framing = 0;
    reg [7:0] rb;
    integer rk;
    always begin
        @(negedge board_tx);
        #(BIT_NS / 2.0);
        if (board_tx !== 1'b0) rx_framing = rx_framing + 1;
        for (rk = 0; rk < 8; rk = rk + 1) begin #(BIT_NS); rb[rk] = board_tx; end
        #(BIT_NS);
        if (board_tx !== 1'b1) rx_framing = rx_framing + 1;
        rxq[rx_w % 65536] = rb;
        rx_w = rx_w + 1;
    end

    task host_get(output [7:0] b, input real timeout_ns);
        real t0;
        begin
            t0 = $realtime;
            while (rx_r == rx_w && $realtime - t0 < timeout_ns) #(BIT_NS);
            if (rx_r == rx_w) begin
                $display("FAIL %0t: no byte from the board within %0.0f us", $time, timeout_ns / 1000.0);
                errors = errors + 1;
                b = 8'h00;
                $display("FAIL: %0d errors", errors);
                $finish_and_return(1);
            end
            b = rxq[rx_r % 65536];
            rx_r = rx_r + 1;
        end
    endtask

    task fail(input [8*80-1:0] what);
        begin
            errors = errors + 1;
            $display("FAIL %0t: %0s", $time, what);
        end
    endtask
