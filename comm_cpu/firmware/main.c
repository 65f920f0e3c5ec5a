/*
 * rcsim communication firmware -- start-up in C and the main loop (the paper's main_routine).
 */
#include "fw.h"

/* ---- state ----------------------------------------------------------------------------- */
unsigned ticks;
unsigned unexpected;
unsigned char step[NO_PORT];
unsigned char gen[NO_PORT];

/* 20 KB per port above the system area: first 10 KB receive, last 10 KB transmit */
unsigned char *rxbuf[NO_PORT] = {
    (unsigned char *)BUF_BASE,
    (unsigned char *)(BUF_BASE + BUF_SIZE),
    (unsigned char *)(BUF_BASE + 2 * BUF_SIZE)
};
unsigned char *txbuf[NO_PORT] = {
    (unsigned char *)(BUF_BASE + RXBUF_SIZE),
    (unsigned char *)(BUF_BASE + BUF_SIZE + RXBUF_SIZE),
    (unsigned char *)(BUF_BASE + 2 * BUF_SIZE + RXBUF_SIZE)
};
unsigned area[NO_PORT] = { 0 * AREA, 1 * AREA, 2 * AREA };

/* Line set-up, in initialised data so that a ROM image can be patched for other baud rates,
 * formats or crystals (docs/firmware.md "Patching the line set-up"). */
unsigned port_div[NO_PORT] = { BAUD_DIV, BAUD_DIV, BAUD_DIV };   /* BRGA divisor */
unsigned char port_lcr[NO_PORT] = { LCR_8E1, LCR_8E1, LCR_8E1 }; /* LCR without DLAB */
unsigned tick_div = TICK_DIV;                                      /* BRGB: 1 ms */

unsigned rx_len[NO_PORT], rx_fwd[NO_PORT], rx_t[NO_PORT];
unsigned char rx_sum[NO_PORT], rx_bad[NO_PORT];
unsigned char chunk_out[NO_PORT];
unsigned chunk_t[NO_PORT];

unsigned char tx_have[NO_PORT], txq_head[NO_PORT], chunk_pending[NO_PORT];
unsigned txq_len[NO_PORT][TXQ];
unsigned tx_rd[NO_PORT], tx_wr[NO_PORT], tx_used[NO_PORT], tx_part[NO_PORT];
unsigned tx_pos[NO_PORT];
unsigned tx_t[NO_PORT], tx_wait[NO_PORT];
unsigned char tx_try[NO_PORT], tx_whole[NO_PORT], txe_wait[NO_PORT];
unsigned t1_lim[NO_PORT];
unsigned char reset_due[NO_PORT], quenched[NO_PORT];
unsigned quench_t[NO_PORT];
unsigned char fresh[NO_PORT];

unsigned n_good[NO_PORT], n_nak[NO_PORT], n_busy[NO_PORT], n_gap[NO_PORT];
unsigned n_sent[NO_PORT], n_retry[NO_PORT], n_fail[NO_PORT], n_coll[NO_PORT];
unsigned n_lerr[NO_PORT], n_break[NO_PORT], n_reset[NO_PORT], n_badmb;
unsigned n_stale[NO_PORT], n_quench[NO_PORT], n_deferred[NO_PORT];
unsigned char rbt_seen[NO_PORT];
unsigned rbt_t[NO_PORT];

/* comm -> main mailbox words wait here until int2rbt is free */
#define MBQ 16
static unsigned char mbq[MBQ];
static unsigned char mb_head, mb_tail;
static unsigned mb_t;
unsigned n_mblost;
unsigned n_implicit;                 /* last chunks taken as ACKed through pflag */

/* ---- int2rbt mailbox ------------------------------------------------------------------- */
void mb_post(unsigned char word)
{
    unsigned f = irq_off();
    unsigned next = (mb_tail + 1) & (MBQ - 1);

    if (next != mb_head) {
        mbq[mb_tail] = word;
        mb_tail = next;
    } else {
        ++n_mblost;
    }
    irq_restore(f);
}

/* Write the oldest queued word to int2rbt once the main CPU has emptied it (reads 0), or
 * MB_WAIT_MS after the previous word if it never does. */
static void mb_pump(void)
{
    unsigned f, w;

    if (mb_head == mb_tail)
        return;
    if (dp_rd(INT2RBT) != 0 && ticks - mb_t < MB_WAIT_MS)
        return;
    f = irq_off();
    w = mbq[mb_head];
    mb_head = (mb_head + 1) & (MBQ - 1);
    irq_restore(f);
    dp_wr(INT2RBT, w);                  /* raises INT_R on the main CPU */
    mb_t = ticks;
}

/* ---- host -> main CPU: forward the received frame through DP-RAM ------------------------ */

/* Step 1 and 2 (the paper's write_data_to_dpram): a full chunk whenever 339 bytes are
 * waiting, the rest (with ETX) once the frame is good; step 2 ends when its last chunk
 * has been consumed. */
static void to_dpram(int port)
{
    unsigned char *b;
    unsigned a, have, n, i, f, s, g;

    if (chunk_out[port]) {
        /* The main CPU frees pflag before it ACKs the last chunk: if that ACK word got lost
         * (overwritten in int2ext), pflag still tells us the frame was consumed. */
        if (step[port] == ST_DONE && rx_fwd[port] == rx_len[port] &&
            dp_rd(PFLAG(port)) != EXT_USE) {
            chunk_out[port] = 0;
            ++n_implicit;
        }
        return;
    }
    f = irq_off();
    s = step[port];
    have = rx_len[port];
    irq_restore(f);
    n = have - rx_fwd[port];
    if (s == ST_RECV) {
        if (n < CHUNK)
            return;
        n = CHUNK;
    } else if (s == ST_DONE) {
        if (n == 0) {
            /* the main CPU frees pflag when it consumes the last chunk; make sure */
            f = irq_off();
            if (step[port] == ST_DONE) {
                if (dp_rd(PFLAG(port)) == EXT_USE)
                    dp_wr(PFLAG(port), P_FREE);
                step[port] = ST_IDLE;
                if (reset_due[port])    /* a reset waited for the frame (port_reset): now */
                    port_reset_now(port, reset_due[port] & 2);
            }
            irq_restore(f);
            return;
        }
        if (n > CHUNK)
            n = CHUNK;
    } else {
        return;
    }
    a = area[port];
    b = rxbuf[port] + rx_fwd[port];
    g = gen[port];
    for (i = 0; i < n; i++)
        dp_wr(a + i, b[i]);
    f = irq_off();
    if (g == gen[port]) {               /* no port reset while we copied */
        dp_wr(PFLAG(port), EXT_USE);
        rx_fwd[port] += n;
        chunk_t[port] = ticks;
        chunk_out[port] = 1;
        mb_post(MB_CHUNK | port);
    }
    irq_restore(f);
}

/* Step 1 timeouts: T1 for the first byte after our ACK has left the line (t1_lim), T2 between
 * bytes (read to read, i.e. stop bit to stop bit). */
static void rx_watch(int port)
{
    unsigned f = irq_off();
    unsigned t = ticks - rx_t[port];

    if (step[port] == ST_RECV &&
        (rx_len[port] ? t > T2_MS : !txe_wait[port] && t > t1_lim[port])) {
        step[port] = ST_DROP;
        ++n_gap[port];
    }
    irq_restore(f);
}

/* Step 3: a dropped frame.  Wait for a chunk in flight, tell the main CPU to discard what it
 * already got (0x3p), free pflag, back to idle. */
static void rx_drop(int port)
{
    unsigned f;

    if (chunk_out[port])
        return;
    f = irq_off();
    if (step[port] == ST_DROP) {
        if (rx_fwd[port])
            mb_post(MB_RESET | port);
        dp_wr(PFLAG(port), P_FREE);
        rx_len[port] = 0;
        rx_fwd[port] = 0;
        rx_bad[port] = 0;       /* the dropped frame's line errors must not refuse the next ENQ */
        step[port] = ST_IDLE;
    }
    irq_restore(f);
}

/* ---- main CPU -> host: send the frame in txbuf ------------------------------------------ */

static void start_tx(int port)
{
    unsigned f = irq_off();

    if (step[port] == ST_IDLE && tx_have[port]) {
        tx_wait[port] = 0;
        tx_t[port] = ticks;
        step[port] = ST_SEND_ENQ;
    }
    irq_restore(f);
}

/* Step 10: ENQ once the back-off has passed. */
static void send_enq(int port)
{
    unsigned f;

    if (ticks - tx_t[port] < tx_wait[port])
        return;
    f = irq_off();
    if (step[port] == ST_SEND_ENQ) {
        outb(UART_BASE(port) + U_TXD, ENQ);
        fresh[port] = 0;
        step[port] = ST_WAIT_ACK;
        txe_wait[port] = 1;             /* T1 starts when the ENQ has left the line */
        ger_update(port);
    }
    irq_restore(f);
}

/* Step 12 is interrupt driven (tx_fill in isr.c); the main loop only tops the FIFO up as well,
 * should a Tx FIFO interrupt ever be missed. */
static void send_data(int port)
{
    unsigned f = irq_off();

    tx_fill(port);
    irq_restore(f);
}

/* Steps 11 and 13: T1 without ACK / EOT -> retry.  T1 runs from the moment our ENQ or ETX
 * has left the line (tx_idle) to the START bit of the answer, which we have one character later:
 * t1_lim = T1 + one character.  "> t1_lim" ticks is more than t1_lim ms whatever the phase of the
 * tick. */
static void tx_watch(int port)
{
    unsigned f = irq_off();

    if ((step[port] == ST_WAIT_ACK || step[port] == ST_WAIT_EOT) && !txe_wait[port] &&
        ticks - tx_t[port] > t1_lim[port])
        tx_retry(port);
    irq_restore(f);
}

/* A port quenched after an overrun (isr.c quench): after QUENCH_MS its receiver interrupts come
 * back, with the RX FIFO and the overrun that piled up meanwhile dropped. */
static void quench_watch(int port)
{
    unsigned b = UART_BASE(port);
    unsigned f;

    if (ticks - quench_t[port] < QUENCH_MS)
        return;
    f = irq_off();
    if (quenched[port]) {
        outb(b + U_RCM, RCM_START);
        inb(b + U_RST);
        quenched[port] = 0;
        ger_update(port);
    }
    irq_restore(f);
}

/* An area the main CPU claimed (RBT_USE) and then abandoned -- e.g. it aborted a frame on a port
 * reset that crossed its claim -- would NAK the host forever.  After AREA_STALE_MS without a
 * chunk word (and no chunk of ours waiting for ring space) free it and drop the partial frame. */
static void area_watch(int port)
{
    unsigned f;

    if (chunk_pending[port] || dp_rd(PFLAG(port)) != RBT_USE) {
        rbt_seen[port] = 0;
        return;
    }
    if (!rbt_seen[port]) {
        rbt_seen[port] = 1;
        rbt_t[port] = ticks;
        return;
    }
    if (ticks - rbt_t[port] < AREA_STALE_MS)
        return;
    f = irq_off();
    if (tx_wr[port] < tx_part[port])
        tx_wr[port] += TXBUF_SIZE;
    tx_wr[port] -= tx_part[port];
    tx_used[port] -= tx_part[port];
    tx_part[port] = 0;
    dp_wr(PFLAG(port), P_FREE);
    rbt_seen[port] = 0;
    ++n_stale[port];
    irq_restore(f);
}

/* ---- the main loop -------------------------------------------------------------------- */
void main_loop(void)
{
    int port;

    for (;;) {
        for (port = 0; port < NO_PORT; port++) {
            switch (step[port]) {
            case ST_IDLE:
                if (tx_have[port])
                    start_tx(port);
                break;
            case ST_RECV:
                rx_watch(port);
                to_dpram(port);
                break;
            case ST_DONE:
                to_dpram(port);
                break;
            case ST_DROP:
                rx_drop(port);
                break;
            case ST_RESET:
                port_reinit(port);      /* asked for by a handler or below */
                break;
            case ST_SEND_ENQ:
                send_enq(port);
                break;
            case ST_WAIT_ACK:
            case ST_WAIT_EOT:
                tx_watch(port);
                break;
            case ST_SEND:
                send_data(port);
                break;
            default:
                break;
            }
            if (chunk_pending[port])
                take_chunk(port);
            area_watch(port);
            if (quenched[port])
                quench_watch(port);
            if (chunk_out[port] && step[port] != ST_RESET && ticks - chunk_t[port] >= DP_ACK_MS)
                port_reset_now(port, 1);    /* the main CPU never consumed the chunk: next pass */
        }
        mb_pump();
    }
}

/*
 * T1 + one character of port p's format, in ticks: T1 ends at the START bit of the answer
 * (docs/serial.md "Protocol timers") and the 82510 has the character at the end of its first
 * stop bit.  One bit is 32 x div / f, one tick 2 x tick_div / f, so a character of `bits' bits
 * is bits x 16 x div / tick_div ticks (rounded up; the crystal cancels out).
 */
static unsigned t1_ticks(int port)
{
    unsigned lcr = port_lcr[port];
    unsigned bits = 1 + 5 + (lcr & 0x03) + ((lcr & 0x08) ? 1 : 0) + ((lcr & 0x04) ? 2 : 1);

    return T1_MS + mul_div_up(bits * 16, port_div[port], tick_div);
}

int main(void)
{
    int port;

    pic_init();
    for (port = 0; port < NO_PORT; port++) {
        t1_lim[port] = t1_ticks(port);
        uart_init(port);
        ger_update(port);
        dp_wr(PFLAG(port), P_FREE);
    }
    dp_rd(INT2EXT);                     /* drop a stale INT_L so that IR3 sees edges */
    dp_wr(INT2EXT, 0);
    irq_on();
    main_loop();
    return 0;
}
