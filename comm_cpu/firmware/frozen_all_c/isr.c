/*
 * rcsim communication firmware -- interrupt service routines.
 *
 * rs232_isr:  IR0..IR2, one 82510 each (and the 1 ms tick on 82510 #0).  Runs with IF = 0;
 *             the entry stub in crt0.s sends the rotate-on-non-specific EOI after it.
 * dpram_isr:  IR3, the IDT7130 INT_L mailbox int2ext.  Reads and empties the mailbox, sends
 *             the EOI, then runs with IF = 1 so that the RS-232 interrupts (and the next
 *             mailbox word) are served while it copies a chunk (see docs/firmware.md).
 */
#include "fw.h"

static int is_hex(unsigned char c)
{
    return (c >= '0' && c <= '9') || (c >= 'A' && c <= 'F');
}

static unsigned char hex_val(unsigned char c)
{
    return c <= '9' ? c - '0' : c - 'A' + 10;
}

static void send(int port, unsigned char c)
{
    outb(UART_BASE(port) + U_TXD, c);
}

/* ENQ from the host: ACK and start receiving if the port's DP-RAM area is free, else NAK. */
static int accept_enq(int port)
{
    if (!(rx_bad[port] & BAD_LINE) && dp_rd(PFLAG(port)) == P_FREE) {
        dp_wr(PFLAG(port), EXT_USE);
        send(port, ACK);
        rx_len[port] = 0;
        rx_fwd[port] = 0;
        rx_sum[port] = 0;
        rx_bad[port] = 0;
        rx_t[port] = ticks;
        fresh[port] = 0;
        step[port] = ST_RECV;
        txe_wait[port] = 1;             /* T1 for the first byte starts when the ACK has left */
        ger_update(port);
        return 1;
    }
    send(port, NAK);
    rx_bad[port] = 0;
    ++n_busy[port];
    return 0;
}

/* ETX seen: check the frame and answer EOT (good) or NAK (dropped). */
static void rx_end(int port)
{
    unsigned char *b = rxbuf[port];
    unsigned n = rx_len[port];
    unsigned char c1, c2, sum;
    int ok;

    ok = rx_bad[port] == 0 && n >= MIN_FRAME && is_hex(b[4]) && is_hex(b[5]);
    if (ok) {
        c1 = b[n - 3];
        c2 = b[n - 2];
        ok = is_hex(c1) && is_hex(c2);
        if (ok) {
            sum = rx_sum[port] - c1 - c2;
            ok = sum == ((hex_val(c1) << 4) | hex_val(c2));
        }
    }
    if (ok) {
        send(port, EOT);
        step[port] = ST_DONE;
        ++n_good[port];
    } else {
        send(port, NAK);
        step[port] = ST_DROP;
        ++n_nak[port];
    }
}

/*
 * Step 12 (the paper's send_data_to_port), interrupt driven: fill the 4-byte TX FIFO from the
 * frame being sent; the Tx FIFO interrupt (enabled while sending, threshold 0 = empty) asks for
 * the next bytes while the last one is still in the shifter, so the frame leaves without gaps
 * even while the main loop or a DP-RAM copy is busy.  When the last byte (ETX) is in the FIFO
 * the interrupt is switched off; T1 for the EOT starts when ETX has left the line (tx_idle).
 * IF = 0.
 */
void tx_fill(int port)
{
    unsigned b = UART_BASE(port);
    unsigned char *d = txbuf[port];
    unsigned len = txq_len[port][txq_head[port]];
    unsigned i;

    if (step[port] != ST_SEND)
        return;
    while (tx_pos[port] < len && (inb(b + U_FLR) & FLR_TFL) < TXFIFO_DEPTH) {
        i = tx_rd[port] + tx_pos[port]++;
        if (i >= TXBUF_SIZE)
            i -= TXBUF_SIZE;
        outb(b + U_TXD, d[i]);
    }
    if (tx_pos[port] >= len) {
        step[port] = ST_WAIT_EOT;
        txe_wait[port] = 1;
        ger_update(port);
    }
}

/*
 * Tx machine interrupt: the transmitter is idle, the last character we wrote has left the line
 * (its stop bit is over).  The timer for the answer to it starts now, as the host's does
 * (docs/serial.md "Protocol timers"): T1 for the ACK to our ENQ, for the EOT to our ETX, for the
 * first frame byte after our ACK.  IF = 0.
 */
static void tx_idle(int port)
{
    unsigned s = step[port];

    if (txe_wait[port]) {
        txe_wait[port] = 0;
        if (s == ST_WAIT_ACK || s == ST_WAIT_EOT)
            tx_t[port] = ticks;
        if (s == ST_WAIT_EOT)
            tx_whole[port] = 1;
        if (s == ST_RECV && rx_len[port] == 0)
            rx_t[port] = ticks;
    }
    ger_update(port);
}

/* The frame being sent is done with (EOT, or given up): drop it from the ring; the next queued
 * frame follows. */
static void tx_next(int port)
{
    unsigned len = txq_len[port][txq_head[port]];
    unsigned rd = tx_rd[port] + len;

    if (rd >= TXBUF_SIZE)
        rd -= TXBUF_SIZE;
    tx_rd[port] = rd;
    tx_used[port] -= len;
    txq_head[port] = (txq_head[port] + 1) & (TXQ - 1);
    --tx_have[port];
    tx_try[port] = 0;
    tx_whole[port] = 0;
    step[port] = ST_IDLE;
}

/*
 * NAK or timeout while sending: back off 10 ms x attempt and start again with ENQ, at most
 * MAX_RETRY times; then give up on this frame only: it is dropped, the main CPU is told which
 * way (0x4p: it never left whole, the host cannot have it; 0x5p: it left whole at least once
 * but no EOT came, the host may have it), and the next queued frame follows.  IF = 0.
 */
void tx_retry(int port)
{
    if (++tx_try[port] > MAX_RETRY) {
        ++n_fail[port];
        mb_post((tx_whole[port] ? MB_GAVE_UP_TX : MB_GAVE_UP) | port);
        tx_next(port);
        return;
    }
    tx_wait[port] = RETRY_MS * tx_try[port];
    tx_t[port] = ticks;
    step[port] = ST_SEND_ENQ;
    ++n_retry[port];
}

/* The protocol for one received byte outside step 1 (step 1 is handled inline in rs232_isr:
 * together they are the paper's rs232_interrupt_service). */
void rx_char(int port, unsigned char c)
{
    unsigned char line_err;

    line_err = rx_bad[port] & BAD_LINE;
    switch (step[port]) {
    case ST_IDLE:
        if (c == ENQ)
            accept_enq(port);
        else
            rx_bad[port] = 0;
        break;
    case ST_SEND_ENQ:
    case ST_WAIT_ACK:
        if (c == ENQ) {
            /* collision: the external system wins if the area is free */
            if (accept_enq(port))
                ++n_coll[port];
        } else if (line_err) {
            rx_bad[port] = 0;
        } else if (step[port] == ST_WAIT_ACK) {
            if (c == ACK) {
                tx_pos[port] = 0;
                step[port] = ST_SEND;
                ger_update(port);
                tx_fill(port);
            } else if (c == NAK) {
                tx_retry(port);
            }
        }
        break;
    case ST_WAIT_EOT:
        if (line_err)
            rx_bad[port] = 0;
        else if (c == EOT) {
            tx_next(port);
            ++n_sent[port];
        }
        else if (c == NAK)
            tx_retry(port);
        break;
    case ST_SEND:
        /* our frame is going out: a NAK now would land in the middle of it */
        rx_bad[port] = 0;
        break;
    default:
        /* frame complete or being dropped: the port is busy */
        if (c == ENQ) {
            send(port, NAK);
            ++n_busy[port];
        }
        rx_bad[port] = 0;
        break;
    }
}

/* BREAK: reset the port once; further BREAK reports before the port is used just flush. */
static void line_break(int port)
{
    ++n_break[port];
    if (!fresh[port])
        port_reset(port, 1);
    else
        outb(UART_BASE(port) + U_RCM, RCM_START);
}

/*
 * An overrun: characters come faster than we take them (a 9600-bps port never overruns, test
 * ThreePortsAtOnceKeepEveryByte), so the line is flooding us.  Its receiver interrupts stay off
 * for QUENCH_MS (the main loop turns them on again) so that the other ports and the main loop
 * keep their time; what arrives meanwhile is lost, as it would be anyway.
 */
static void quench(int port)
{
    quenched[port] = 1;
    quench_t[port] = ticks;
    ++n_quench[port];
    ger_update(port);
    outb(UART_BASE(port) + U_RCM, RCM_START);
}

/* Rx machine status: BREAK resets the port, an error spoils the frame being received. */
static void line_status(int port, unsigned char st)
{
    if (st & RST_BKD) {
        line_break(port);
    } else if (st & (RST_OE | RST_PE | RST_FE)) {
        rx_bad[port] |= BAD_LINE;
        ++n_lerr[port];
        if (st & RST_OE)
            quench(port);
    }
}

/*
 * IR0..IR2.  Works in bank 1; if the interrupted code had another bank selected, that bank is
 * restored on the way out.  Handles the pending sources until GIR shows none, so that INT falls
 * and the edge-triggered 8259A sees the next request -- but at most ISR_VISITS of them (each
 * received character is one) per interrupt.  Whatever is still pending then is left for the
 * next interrupt, which ICM.INTA requests (INT falls and rises again: a fresh edge) and which
 * the rotating priority serves after the other ports: a port that receives faster than we can
 * read cannot hold the others off (docs/firmware.md "Interrupts").  GIR is read before every
 * character, so an error status (Rx machine, latched when its character arrived, ranks above
 * the Rx FIFO) is seen before the character.
 */
void rs232_isr(int port)
{
    unsigned b = UART_BASE(port);
    unsigned gir, bank, c, k, n;

    gir = inb(b + U_GIR);               /* the pending source and the current bank */
    bank = gir & BANK_MASK;
    if (bank != BANK_WORK)
        outb(b + U_BANK, BANK_WORK);
    for (n = ISR_VISITS; !(gir & GIR_NONE); --n) {
        if (!n) {
            outb(b + U_ICM, ICM_INTA);  /* the rest in the next interrupt */
            break;
        }
        gir &= GIR_VEC;
        if (gir == GIR_RXF) {
            c = inb(b + U_RXD);
            if (step[port] != ST_RECV) {
                rx_char(port, c);
            } else {
                /* step 1: store, check, keep the running sum of everything after SOH */
                rx_t[port] = ticks;
                k = rx_len[port];
                if (k >= MAX_FRAME) {
                    rx_bad[port] |= BAD_LONG;
                    if (c == ETX)
                        rx_end(port);
                } else {
                    rxbuf[port][k] = c;
                    rx_len[port] = k + 1;
                    if (c == ETX) {
                        rx_end(port);
                    } else {
                        if (c >= 0x20 && c <= 0x7E) {
                            if (k == 0 || k == 3)
                                rx_bad[port] |= BAD_CHAR;   /* SOH or STX expected here */
                        } else if (!(k == 0 && c == SOH) && !(k == 3 && c == STX)) {
                            rx_bad[port] |= BAD_CHAR;
                        }
                        if (k)
                            rx_sum[port] += c;
                    }
                }
            }
        } else if (gir == GIR_TIMER) {
            inb(b + U_TMST);            /* clears TBEx; BRGB reloads by itself */
            ++ticks;
        } else if (gir == GIR_RXM) {
            line_status(port, inb(b + U_RST));
        } else if (gir == GIR_TXF) {
            if (step[port] == ST_SEND)
                tx_fill(port);
            else
                ger_update(port);       /* nothing to send (port reset, retry) */
        } else if (gir == GIR_TXM) {
            tx_idle(port);
        } else {
            inb(b + U_GSR);
            inb(b + U_MSR);
        }
        gir = inb(b + U_GIR);
    }
    if (bank != BANK_WORK)
        outb(b + U_BANK, bank);
}

/*
 * Copy one chunk of a frame for the host from data[p] into the txbuf ring (the paper's
 * DP-RAM_interrupt_service loop: byte by byte up to ETX or 339 bytes), then ACK it.  The chunk
 * holding ETX completes the frame: it is queued for sending (step 10 from the main loop) and
 * pflag[p] is freed (the reader frees it) before the ACK word.  Without room for a whole chunk
 * the chunk stays in DP-RAM unacknowledged (chunk_pending) until a frame has been sent.
 * Runs in dpram_isr with IF = 1, or from the main loop for a pending chunk.
 */
void take_chunk(int port)
{
    unsigned char *b = txbuf[port];
    unsigned a = area[port];
    unsigned char g = gen[port];
    unsigned w, i, f;
    unsigned char c, last, room;

    f = irq_off();
    room = tx_used[port] <= TXBUF_SIZE - CHUNK && tx_have[port] < TXQ;
    chunk_pending[port] = !room;
    irq_restore(f);
    if (!room)
        return;
    w = tx_wr[port];
    last = 0;
    for (i = 0; i < CHUNK && !last; i++) {
        c = dp_rd(a + i);
        b[w] = c;
        if (++w == TXBUF_SIZE)
            w = 0;
        last = c == ETX;
    }
    f = irq_off();
    if (g == gen[port]) {
        tx_wr[port] = w;
        tx_used[port] += i;
        tx_part[port] += i;
        if (last) {
            txq_len[port][(txq_head[port] + tx_have[port]) & (TXQ - 1)] = tx_part[port];
            tx_part[port] = 0;
            ++tx_have[port];
            dp_wr(PFLAG(port), P_FREE);
        }
        mb_post(MB_ACK | port);
    }
    irq_restore(f);
}

/* One mailbox word from the main CPU. */
void dp_event(unsigned char word)
{
    int port = word & 0x0F;

    if (port >= NO_PORT) {
        ++n_badmb;
        return;
    }
    switch (word & 0xF0) {
    case MB_CHUNK:
        rbt_seen[port] = 0;
        take_chunk(port);
        break;
    case MB_ACK:
        chunk_out[port] = 0;
        break;
    case MB_RESET:
        port_reset(port, 0);
        break;
    default:
        ++n_badmb;
        break;
    }
}

void dpram_isr(void)
{
    unsigned char w;

    w = dp_rd(INT2EXT);                             /* clears INT_L */
    dp_wr(INT2EXT, 0);                              /* the mailbox is free again */
    outb(PIC_A0, PIC_EOI_ROT);                      /* IR3 may request again at once */
    irq_on();                                       /* RS-232 (and DP-RAM) may nest */
    dp_event(w);
    irq_off();
}
