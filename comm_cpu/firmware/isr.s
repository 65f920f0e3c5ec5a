! rcsim communication firmware -- the interrupt paths in assembly (as86 -0 syntax).
!
!   _isr_port0..2   IR0..IR2, one 82510 each (and the 1 ms tick on 82510 #0): the paper's
!                   rs232_interrupt_service.  A per-port entry (macro RS232_ENTRY) handles the
!                   common case -- one received character in step 1 -- with the port's I/O
!                   addresses and variables as constants; everything else goes to the general
!                   loop _rs232_isr and the per-character state machine rx_char.
!   _isr_dpram      IR3, the IDT7130 INT_L mailbox: the paper's DP-RAM_interrupt_service,
!                   with the chunk copy take_chunk.
!   _tx_fill, _tx_retry, _ger_update, _take_chunk: the same paths for the C main loop.
!
! docs/firmware.md describes the behaviour (it is the C firmware's, kept in frozen_all_c/) and
! gives the cycle budget of the common path.
!
! Conventions
! * DS = SS = DATA_SEG from start-up on: nothing changes DS (the DP-RAM is reached through
!   ES), so the entries do not reload it.  ES is scratch; the entries save it where they use it.
! * IF = 0 in the RS-232 paths.  The DP-RAM handler sends its EOI and runs with IF = 1.  No
!   handler resets a port: it asks for the reset (port_reset), the main loop runs it.
! * Inside, a port's routines take BX = port and SI = 2 * port (the index of byte and of word
!   arrays, fw.h: the per-port arrays are C arrays), keep both, and may change AX CX DX DI ES.
! * From C (bcc): arguments on the stack, AX BX CX DX ES scratch, SI DI BP kept.
! * The stack stays word aligned: every push is a word, and the C code has no byte locals.
!
! The constants below are fw.h's (same names); the build checks that they agree
! (check_equates.cmake).

NO_PORT       = 3
TICK_PORT     = 0
DATA_SEG      = 0x0040
BUF_BASE      = 0x0C00
BUF_SIZE      = 0x5000
TXBUF_SIZE    = 0x2800
PIC_A0        = 0xC0
PIC_EOI_ROT   = 0xA0
U_RXD         = 0
U_TXD         = 0
U_GER         = 2
U_GIR         = 4
U_BANK        = 4
U_TMST        = 6
U_FLR         = 8
U_RST         = 10
U_RCM         = 10
U_MSR         = 12
U_GSR         = 14
U_ICM         = 14
BANK_NAS      = 0x00
BANK_WORK     = 0x20
BANK_MASK     = 0x60
GER_TXF       = 0x02
GER_TXM       = 0x10
GER_TIMER     = 0x20
GER_RX        = 0x05
GIR_NONE      = 0x01
GIR_VEC       = 0x0E
GIR_TIMER     = 0x0A
GIR_TXM       = 0x08
GIR_RXM       = 0x06
GIR_RXF       = 0x04
GIR_TXF       = 0x02
RST_OE        = 0x02
RST_BKD       = 0x10
RST_ERRS      = 0x0E          ! OE | PE | FE
RCM_START     = 0xB0
ICM_INTA      = 0x08
FLR_TFL       = 0x07
TXFIFO_DEPTH  = 4
ISR_VISITS    = 1
DP_SEG        = 0xD000
CHUNK         = 339
INT2EXT       = 0x3FE
P_FREE        = 0
EXT_USE       = 1
MB_ACK        = 0x20
MB_CHUNK      = 0x10
MB_RESET      = 0x30
MB_GAVE_UP    = 0x40
MB_GAVE_UP_TX = 0x50
SOH           = 0x01
STX           = 0x02
ETX           = 0x03
EOT           = 0x04
ENQ           = 0x05
ACK           = 0x06
NAK           = 0x15
MIN_FRAME     = 9
MAX_FRAME     = 8201
RETRY_MS      = 10
MAX_RETRY     = 3
TXQ           = 8
ST_IDLE       = 0
ST_RECV       = 1
ST_DONE       = 2
ST_DROP       = 3
ST_RESET      = 4
ST_SEND_ENQ   = 10
ST_WAIT_ACK   = 11
ST_SEND       = 12
ST_WAIT_EOT   = 13
BAD_LINE      = 0x01
BAD_CHAR      = 0x02
BAD_LONG      = 0x04

! GIR values of the common cases: bank 1 selected (BANK_WORK) and ...
GIR_B1_RXF    = 0x24          ! ... a received character pending
GIR_B1_TICK   = 0x2A          ! ... the timer pending
GIR_B1_NONE   = 0x21          ! ... nothing pending

.globl _isr_port0
.globl _isr_port1
.globl _isr_port2
.globl _isr_dpram
.globl _rs232_isr
.globl _dpram_isr
.globl _tx_fill
.globl _tx_retry
.globl _ger_update
.globl _take_chunk
.globl _port_reset
.globl _port_reset_now
! from C (main.c, hw.c)
.globl _reset_due
.globl _n_deferred
.globl _mb_post
.globl _ticks
.globl _step
.globl _gen
.globl _rxbuf
.globl _txbuf
.globl _area
.globl _rx_len
.globl _rx_fwd
.globl _rx_t
.globl _rx_sum
.globl _rx_bad
.globl _chunk_out
.globl _tx_have
.globl _txq_head
.globl _txq_len
.globl _tx_rd
.globl _tx_wr
.globl _tx_used
.globl _tx_part
.globl _chunk_pending
.globl _tx_pos
.globl _tx_t
.globl _tx_wait
.globl _tx_try
.globl _tx_whole
.globl _txe_wait
.globl _quenched
.globl _quench_t
.globl _fresh
.globl _rbt_seen
.globl _n_good
.globl _n_nak
.globl _n_busy
.globl _n_sent
.globl _n_retry
.globl _n_fail
.globl _n_coll
.globl _n_lerr
.globl _n_break
.globl _n_quench
.globl _n_badmb

.data
.even
uart_io:                        ! I/O address of each 82510 (register 0: RXD / TXD)
	.word	0x80, 0x90, 0xA0

.text

! ---- IR0..IR2: the per-port entry ----------------------------------------------------------
! ?1 = the port, ?2 = its 82510's I/O address, ?3 = its receive buffer (DS offset, = rxbuf[?1]).
! AH counts the sources this interrupt may still handle (ISR_VISITS, docs/firmware.md "Bounded
! work"); AL is the GIR as read.  The entry handles one source (and on TICK_PORT a tick after it),
! never loops: whatever is still pending goes to the general loop with the visits left.  Each
! call of the general loop has AH constant (ISR_VISITS - 1 after a visit here, ISR_VISITS without),
! so `rcsim bound` bounds every path by that one counter (docs/firmware.md "The bound").
! On TICK_PORT the tick alone (GIR "bank 1, timer", then nothing) is counted with AX saved only,
! 1000 times a second.  The common case stays here: GIR reads "bank 1, Rx FIFO", the
! port is in step 1 and the character is a printable one at position 4 or later of a frame that
! is not overlong -- store it, count it, add it to the sum, note the time (the step-1 code of
! rx_store, without the checks it cannot need).  Anything else -- another GIR value (another
! source, another bank), another step, a control byte, positions 0..3 -- goes to the general
! code, which handles every case.  The 82510's INT falls when GIR shows nothing pending, so the
! edge-triggered 8259A sees the next request; then the rotate-on-non-specific EOI.
MACRO RS232_ENTRY
.even
_isr_port?1:
	push	ax
	in	al,?2+U_GIR
	cmp	al,#GIR_B1_RXF
	jne	p?1_first_other
	push	bx
	mov	ah,#ISR_VISITS
	in	al,?2+U_RXD
	cmp	byte ptr [_step+?1],#ST_RECV
	jne	p?1_char
	mov	bx,[_rx_len+2*?1]       ! k: the character's position in the frame
	cmp	bx,#MAX_FRAME
	jae	p?1_char
	cmp	bx,*4
	jb	p?1_char
	cmp	al,#0x20
	jb	p?1_char
	cmp	al,#0x7E
	ja	p?1_char
	mov	?3[bx],al               ! rxbuf[?1][k] = c
	inc	bx
	mov	[_rx_len+2*?1],bx
	add	[_rx_sum+?1],al
	mov	bx,[_ticks]
	mov	[_rx_t+2*?1],bx         ! T2 runs from here
p?1_visited:
	dec	ah
	in	al,?2+U_GIR
	cmp	al,#GIR_B1_NONE
	jne	p?1_more
p?1_eoi:
	mov	al,#PIC_EOI_ROT
	out	PIC_A0,al
	pop	bx
	pop	ax
	iret
p?1_more:
IF ?1 = TICK_PORT
	cmp	al,#GIR_B1_TICK         ! the tick after the first source: AX is all it needs
	jne	p?1_left
	in	al,?2+U_TMST            ! clears TBEx; BRGB reloads by itself
	inc	word ptr [_ticks]
	in	al,?2+U_GIR
	cmp	al,#GIR_B1_NONE
	je	p?1_eoi
ENDIF
p?1_left:
	or	ah,ah                   ! visits left: the general loop takes the rest
	jnz	p?1_general
	mov	al,#ICM_INTA            ! none left: ICM.INTA here (INT falls and rises again, the
	out	?2+U_ICM,al             ! rest in the next interrupt), without the general loop's
	jmp	p?1_eoi                 ! entry and exit.  Bank 1 is selected: the entry's GIR said
	                                ! so, and only _rs232_isr selects banks (it restores them)
p?1_general:
	mov	bx,#?1
	call	_rs232_isr
	jmp	p?1_eoi
p?1_char:
	push	ax
	mov	bx,#?1
	call	rx_char_entry
	pop	ax
	jmp	p?1_visited
p?1_first_other:
IF ?1 = TICK_PORT
	cmp	al,#GIR_B1_TICK         ! the tick alone: AX is all it needs
	jne	p?1_first_general
	in	al,?2+U_TMST
	inc	word ptr [_ticks]
	in	al,?2+U_GIR
	cmp	al,#GIR_B1_NONE
	jne	p?1_after_tick
	mov	al,#PIC_EOI_ROT
	out	PIC_A0,al
	pop	ax
	iret
p?1_after_tick:
	push	bx
	mov	ah,#ISR_VISITS-1
	jmp	p?1_general
ENDIF
p?1_first_general:                      ! its own call: AH is one constant on each way in
	push	bx
	mov	ah,#ISR_VISITS
	mov	bx,#?1
	call	_rs232_isr
	jmp	p?1_eoi
MEND

RS232_ENTRY(0,0x80,0x0C00)
RS232_ENTRY(1,0x90,0x5C00)
RS232_ENTRY(2,0xA0,0xAC00)

! ---- the general RS-232 service ------------------------------------------------------------
! In: AL = GIR as read, AH = sources this interrupt may still handle, BX = port.  IF = 0.
! Works in bank 1; if the interrupted code had another bank selected, that bank is restored on
! the way out.  Handles the pending sources until GIR shows none, at most AH of them; with one
! still pending after that it writes ICM.INTA (INT falls and rises again: a fresh edge the 8259A
! serves after the other ports).  GIR is read before every character, so an error status (Rx
! machine, latched when its character arrived, ranks above the Rx FIFO) is seen before the
! character.  Changes AX, BX.
.even
_rs232_isr:
	push	cx
	push	dx
	push	si
	push	di
	push	es
	mov	si,bx
	add	si,si
	mov	dx,uart_io[si]
	mov	cx,ax                   ! CL = GIR, CH = sources left
	and	al,#BANK_MASK
	push	ax                      ! the bank found
	cmp	al,#BANK_WORK
	je	rs_loop
	add	dx,*U_BANK
	mov	al,#BANK_WORK
	out	dx,al
	sub	dx,*U_BANK
rs_loop:
	test	cl,#GIR_NONE
	jnz	rs_end
	or	ch,ch
	jnz	rs_visit
	add	dx,*U_ICM
	mov	al,#ICM_INTA            ! the rest in the next interrupt
	out	dx,al
	sub	dx,*U_ICM
	jmp	rs_end
rs_visit:
	dec	ch
	push	cx
	push	dx
	and	cl,#GIR_VEC
	call	rs_source
	pop	dx
	pop	cx
	add	dx,*U_GIR
	in	al,dx
	sub	dx,*U_GIR
	mov	cl,al
	jmp	rs_loop
rs_end:
	pop	ax
	cmp	al,#BANK_WORK
	je	rs_out
	add	dx,*U_BANK
	out	dx,al
rs_out:
	pop	es
	pop	di
	pop	si
	pop	dx
	pop	cx
	ret

! One source: CL = its GIR vector, DX = the 82510's I/O address.
.even
rs_source:
	cmp	cl,#GIR_RXF
	jne	rs_s1
	in	al,dx                   ! RXD
	jmp	rx_char
rs_s1:
	cmp	cl,#GIR_TIMER
	jne	rs_s2
	add	dx,*U_TMST
	in	al,dx                   ! clears TBEx; BRGB reloads by itself
	inc	word ptr [_ticks]
	ret
rs_s2:
	cmp	cl,#GIR_RXM
	jne	rs_s3
	add	dx,*U_RST
	in	al,dx
	br	line_status
rs_s3:
	cmp	cl,#GIR_TXF
	jne	rs_s4
	cmp	byte ptr _step[bx],#ST_SEND
	jne	rs_s3n
	br	tx_fill_r
rs_s3n:
	br	ger_update_r            ! nothing to send (port reset, retry)
rs_s4:
	cmp	cl,#GIR_TXM
	jne	rs_s5
	br	tx_idle
rs_s5:
	add	dx,*U_GSR               ! a source we do not enable: read it away
	in	al,dx
	sub	dx,*U_GSR-U_MSR
	in	al,dx
	ret

! One character from the per-port entry: AL = c, BX = port.  Changes AX, BX.
.even
rx_char_entry:
	push	cx
	push	dx
	push	si
	push	di
	push	es
	mov	si,bx
	add	si,si
	call	rx_char
	pop	es
	pop	di
	pop	si
	pop	dx
	pop	cx
	ret

! ---- the per-character state machine (steps 0, 1, 10, 11, 13; 2, 3, 12 busy) ---------------
! AL = the character.
.even
rx_char:
	mov	cl,_step[bx]
	cmp	cl,#ST_RECV
	jne	rc_0
	jmp	rx_store
rc_0:
	mov	ah,_rx_bad[bx]
	and	ah,#BAD_LINE            ! AH = a line error came with this character
	cmp	cl,#ST_IDLE
	jne	rc_10
	cmp	al,#ENQ
	jne	rc_clear
	br	accept_enq
rc_10:
	cmp	cl,#ST_SEND_ENQ
	je	rc_11
	cmp	cl,#ST_WAIT_ACK
	jne	rc_13
rc_11:
	cmp	al,#ENQ
	jne	rc_11a
	call	accept_enq              ! collision: the external system wins if the area is free
	jz	rc_ret
	inc	word ptr _n_coll[si]
	ret
rc_11a:
	or	ah,ah
	jnz	rc_clear
	cmp	cl,#ST_WAIT_ACK
	jne	rc_ret
	cmp	al,#ACK
	jne	rc_nak
	mov	word ptr _tx_pos[si],*0
	mov	byte ptr _step[bx],#ST_SEND
	br	ger_update_r            ! the Tx FIFO interrupt on: the FIFO is empty, so it asks at
	                                ! once, and its own visit fills it (one visit, one fill)
rc_nak:
	cmp	al,#NAK
	jne	rc_ret
	br	tx_retry_r
rc_13:
	cmp	cl,#ST_WAIT_EOT
	jne	rc_12
	or	ah,ah
	jnz	rc_clear
	cmp	al,#EOT
	jne	rc_nak
	call	tx_next
	inc	word ptr _n_sent[si]
	ret
rc_12:
	cmp	cl,#ST_SEND             ! our frame is going out: a NAK now would land in it
	je	rc_clear
	cmp	al,#ENQ                 ! frame complete or being dropped: the port is busy
	jne	rc_clear
	mov	al,#NAK
	call	send
	inc	word ptr _n_busy[si]
rc_clear:
	mov	byte ptr _rx_bad[bx],#0
rc_ret:
	ret

! Step 1: store, check, keep the running sum of everything after SOH.  AL = c.
rx_store:
	mov	cx,[_ticks]
	mov	_rx_t[si],cx
	mov	di,_rx_len[si]          ! k
	cmp	di,#MAX_FRAME
	jb	st_room
	or	byte ptr _rx_bad[bx],#BAD_LONG
	cmp	al,#ETX
	je	st_end
	ret
st_room:
	mov	cx,di                   ! CX = k
	inc	di
	mov	_rx_len[si],di
	add	di,_rxbuf[si]
	mov	-1[di],al               ! rxbuf[p][k] = c
	cmp	al,#ETX
	je	st_end
	cmp	al,#0x20
	jb	st_ctl
	cmp	al,#0x7E
	ja	st_ctl
	jcxz	st_bad                  ! printable: SOH expected at 0, STX at 3
	cmp	cx,*3
	jne	st_sum
st_bad:
	or	byte ptr _rx_bad[bx],#BAD_CHAR
st_sum:
	jcxz	st_ret
	add	_rx_sum[bx],al
st_ret:
	ret
st_ctl:
	jcxz	st_at0
	cmp	cx,*3
	jne	st_bad
	cmp	al,#STX
	jne	st_bad
	jmp	st_sum
st_at0:
	cmp	al,#SOH
	jne	st_bad
	ret
st_end:
	jmp	rx_end

! ETX seen: at least MIN_FRAME bytes, no line error or bad character, B1 B2 and C1 C2
! uppercase hex, (sum - C1 - C2) & 0xFF = C1C2 -> EOT and step 2, else NAK and step 3.
.even
rx_end:
	cmp	byte ptr _rx_bad[bx],#0
	jne	re_bad
	mov	cx,_rx_len[si]
	cmp	cx,#MIN_FRAME
	jb	re_bad
	mov	di,_rxbuf[si]
	mov	al,4[di]
	call	hex_digit
	jc	re_bad
	mov	al,5[di]
	call	hex_digit
	jc	re_bad
	add	di,cx                   ! DI = past ETX: C1 at -3, C2 at -2
	mov	al,-3[di]
	call	hex_digit
	jc	re_bad
	mov	ah,al
	mov	cl,#4
	shl	ah,cl
	mov	al,-2[di]
	call	hex_digit
	jc	re_bad
	or	ah,al                   ! AH = the check value C1C2
	mov	al,_rx_sum[bx]
	sub	al,-3[di]
	sub	al,-2[di]
	cmp	al,ah
	jne	re_bad
	mov	al,#EOT
	call	send
	mov	byte ptr _step[bx],#ST_DONE
	inc	word ptr _n_good[si]
	ret
re_bad:
	mov	al,#NAK
	call	send
	mov	byte ptr _step[bx],#ST_DROP
	inc	word ptr _n_nak[si]
	ret

! AL = an uppercase hex digit -> AL = its value, CF = 0; anything else: CF = 1.
hex_digit:
	sub	al,#0x30                ! '0'
	jb	hd_bad
	cmp	al,#10
	jb	hd_ok
	sub	al,#0x11                ! 'A' - '0'
	jb	hd_bad
	cmp	al,#6
	jae	hd_bad
	add	al,#10
hd_ok:
	clc
	ret
hd_bad:
	stc
	ret

! AL -> TXD.  Changes DX.
send:
	mov	dx,uart_io[si]
	out	dx,al
	ret

! ENQ from the host: ACK and start receiving if the port's DP-RAM area is free (pflag[p] = 0,
! claimed here with EXT_USE), else NAK.  Returns ZF = 0 when accepted, ZF = 1 on NAK.
.even
accept_enq:
	test	byte ptr _rx_bad[bx],#BAD_LINE
	jnz	ae_nak
	mov	ax,#DP_SEG
	mov	es,ax
	mov	di,_area[si]
	seg	es
	cmp	byte ptr CHUNK[di],#P_FREE      ! pflag[p]
	jne	ae_nak
	seg	es
	mov	byte ptr CHUNK[di],#EXT_USE
	mov	al,#ACK
	call	send
	xor	ax,ax
	mov	_rx_len[si],ax
	mov	_rx_fwd[si],ax
	mov	_rx_sum[bx],al
	mov	_rx_bad[bx],al
	mov	_fresh[bx],al
	mov	ax,[_ticks]
	mov	_rx_t[si],ax
	mov	byte ptr _step[bx],#ST_RECV
	mov	byte ptr _txe_wait[bx],#1       ! T1 for the first byte starts when the ACK has left
	call	ger_update_r
	mov	al,#1
	or	al,al
	ret
ae_nak:
	mov	al,#NAK
	call	send
	mov	byte ptr _rx_bad[bx],#0
	inc	word ptr _n_busy[si]
	xor	ax,ax
	ret

! Rx machine status (AL = RST): BREAK resets the port once (further BREAK reports before the
! port is used just flush); OE/PE/FE spoil the frame being received; an overrun also quenches
! the port: a line that floods us keeps its receiver interrupts off for QUENCH_MS (the main loop
! turns them on again).  The reset is only asked for here (port_reset: step 4, the port's
! sources off); the main loop runs it with interrupts enabled (hw.c port_reinit).
line_status:
	test	al,#RST_BKD
	jz	ls_err
	inc	word ptr _n_break[si]
	cmp	byte ptr _fresh[bx],#0
	jne	ls_flush
	mov	al,#3                   ! reset, and tell the main CPU
	br	reset_ask_r
ls_err:
	test	al,#RST_ERRS
	jz	ls_ret
	or	byte ptr _rx_bad[bx],#BAD_LINE
	inc	word ptr _n_lerr[si]
	test	al,#RST_OE
	jz	ls_ret
	mov	byte ptr _quenched[bx],#1
	mov	ax,[_ticks]
	mov	_quench_t[si],ax
	inc	word ptr _n_quench[si]
	call	ger_update_r
ls_flush:
	mov	dx,uart_io[si]
	add	dx,*U_RCM
	mov	al,#RCM_START
	out	dx,al
ls_ret:
	ret

! ---- sending -------------------------------------------------------------------------------
! GER from the port's state: the tick on TICK_PORT; in step 4 (a reset waits for the main loop)
! nothing else; otherwise the receiver's sources unless quenched, the Tx FIFO while a frame goes
! out (step 12), the Tx machine while a timer waits for the transmitter to be idle.  Bank 0,
! GER, back to bank 1.  IF = 0.  Changes AX, DX.
.even
ger_update_r:
	xor	al,al
	cmp	bx,*TICK_PORT
	jne	gu_1
	mov	al,#GER_TIMER
gu_1:
	cmp	byte ptr _step[bx],#ST_RESET
	je	gu_4
	cmp	byte ptr _quenched[bx],#0
	jne	gu_2
	or	al,#GER_RX
gu_2:
	cmp	byte ptr _step[bx],#ST_SEND
	jne	gu_3
	or	al,#GER_TXF
gu_3:
	cmp	byte ptr _txe_wait[bx],#0
	je	gu_4
	or	al,#GER_TXM
gu_4:
	mov	ah,al
	mov	dx,uart_io[si]
	add	dx,*U_BANK
	mov	al,#BANK_NAS
	out	dx,al
	sub	dx,*U_BANK-U_GER
	mov	al,ah
	out	dx,al
	add	dx,*U_BANK-U_GER
	mov	al,#BANK_WORK
	out	dx,al
	ret

! CX = the length of the frame being sent (txq_len[p][txq_head[p]]).  Changes AX, DI.
txq_len_r:
	mov	di,si
	shl	di,1
	shl	di,1
	shl	di,1                    ! 2 * TXQ * p
	mov	al,_txq_head[bx]
	xor	ah,ah
	add	ax,ax
	add	di,ax
	mov	cx,_txq_len[di]
	ret

! Step 12 (the paper's send_data_to_port), interrupt driven: fill the TX FIFO from the frame
! being sent -- as many bytes as FLR says there is room for.  The Tx FIFO interrupt (enabled
! while sending, threshold 0 = empty) asks for the next ones while the last is still in the
! shifter.  With the last byte (ETX) in the FIFO: step 13, the Tx FIFO interrupt off and the Tx
! machine on (T1 starts when ETX has left the line, tx_idle).  IF = 0.
.even
tx_fill_r:
	cmp	byte ptr _step[bx],#ST_SEND
	jne	tf_ret
	call	txq_len_r               ! CX = len
	sub	cx,_tx_pos[si]          ! CX = bytes not yet given to the 82510
	jbe	tf_end
	mov	dx,uart_io[si]
	add	dx,*U_FLR
	in	al,dx
	sub	dx,*U_FLR
	and	al,#FLR_TFL
	mov	ah,#TXFIFO_DEPTH
	sub	ah,al                   ! AH = room in the FIFO
	jbe	tf_ret
	push	bx
	push	cx
	mov	di,_tx_rd[si]
	add	di,_tx_pos[si]          ! the ring offset of byte tx_pos
	cmp	di,#TXBUF_SIZE
	jb	tf_1
	sub	di,#TXBUF_SIZE
tf_1:
	mov	bx,_txbuf[si]
	add	di,bx                   ! DI = the next byte
	add	bx,#TXBUF_SIZE          ! BX = the end of the ring
tf_loop:
	mov	al,[di]
	out	dx,al                   ! TXD
	inc	di
	cmp	di,bx
	jne	tf_2
	sub	di,#TXBUF_SIZE
tf_2:
	dec	ah
	loopnz	tf_loop                 ! while bytes are left and the FIFO has room
	pop	ax
	sub	ax,cx
	add	_tx_pos[si],ax          ! the bytes given
	pop	bx
	jcxz	tf_end
tf_ret:
	ret
tf_end:
	mov	byte ptr _step[bx],#ST_WAIT_EOT
	mov	byte ptr _txe_wait[bx],#1
	br	ger_update_r

! Tx machine interrupt: the transmitter is idle, the last character we wrote has left the line.
! The timer for the answer starts now, as the host's does (docs/serial.md "Protocol timers"): T1
! for the ACK to our ENQ, for the EOT to our ETX, for the first frame byte after our ACK.
tx_idle:
	cmp	byte ptr _txe_wait[bx],#0
	je	ti_ger
	mov	byte ptr _txe_wait[bx],#0
	mov	al,_step[bx]
	cmp	al,#ST_WAIT_EOT
	jne	ti_1
	mov	byte ptr _tx_whole[bx],#1       ! the frame left whole at least once
	jmp	ti_tx
ti_1:
	cmp	al,#ST_WAIT_ACK
	je	ti_tx
	cmp	al,#ST_RECV
	jne	ti_ger
	cmp	word ptr _rx_len[si],*0
	jne	ti_ger
	mov	ax,[_ticks]
	mov	_rx_t[si],ax
	jmp	ti_ger
ti_tx:
	mov	ax,[_ticks]
	mov	_tx_t[si],ax
ti_ger:
	br	ger_update_r

! The frame being sent is done with (EOT, or given up): drop it from the ring; the next queued
! frame follows.  Changes AX, CX, DI.
tx_next:
	call	txq_len_r
	mov	ax,_tx_rd[si]
	add	ax,cx
	cmp	ax,#TXBUF_SIZE
	jb	tn_1
	sub	ax,#TXBUF_SIZE
tn_1:
	mov	_tx_rd[si],ax
	sub	_tx_used[si],cx
	mov	al,_txq_head[bx]
	inc	al
	and	al,#TXQ-1
	mov	_txq_head[bx],al
	dec	byte ptr _tx_have[bx]
	xor	al,al
	mov	_tx_try[bx],al
	mov	_tx_whole[bx],al
	mov	_step[bx],al            ! ST_IDLE
	ret

! NAK or timeout while sending: back off 10 ms x attempt and start again with ENQ, at most
! MAX_RETRY times; then give up on this frame only: drop it, tell the main CPU which way (0x4p:
! it never left whole, the host cannot have it; 0x5p: it left whole at least once without an
! EOT, the host may have it); the next queued frame follows.  IF = 0.
tx_retry_r:
	inc	byte ptr _tx_try[bx]
	cmp	byte ptr _tx_try[bx],#MAX_RETRY
	ja	tr_give
	mov	al,_tx_try[bx]
	mov	ah,#RETRY_MS
	mul	ah
	mov	_tx_wait[si],ax
	mov	ax,[_ticks]
	mov	_tx_t[si],ax
	mov	byte ptr _step[bx],#ST_SEND_ENQ
	inc	word ptr _n_retry[si]
	ret
tr_give:
	inc	word ptr _n_fail[si]
	mov	al,#MB_GAVE_UP
	cmp	byte ptr _tx_whole[bx],#0
	je	tr_1
	mov	al,#MB_GAVE_UP_TX
tr_1:
	or	al,bl
	call	mb_post_r
	jmp	tx_next

! AL = a word for the main CPU: main.c's queue for int2rbt.  Changes AX, CX, DX, ES.
mb_post_r:
	push	bx
	xor	ah,ah
	push	ax
	call	_mb_post
	inc	sp
	inc	sp
	pop	bx
	ret

! ---- IR3: the DP-RAM mailbox -----------------------------------------------------------------
! Reads int2ext (clears INT_L), empties it (the mailbox is free again), sends the
! rotate-on-non-specific EOI and handles the word with IF = 1, so that the RS-232 interrupts (and
! the next mailbox word) are served during a chunk copy (docs/firmware.md "Interrupts").
.even
_isr_dpram:
	push	ax
	push	bx
	push	cx
	push	dx
	push	si
	push	di
	push	es
	call	_dpram_isr
	pop	es
	pop	di
	pop	si
	pop	dx
	pop	cx
	pop	bx
	pop	ax
	iret

_dpram_isr:
	mov	ax,#DP_SEG
	mov	es,ax
	seg	es
	mov	al,[INT2EXT]            ! clears INT_L
	seg	es
	mov	byte ptr [INT2EXT],#0
	mov	cl,al
	mov	al,#PIC_EOI_ROT         ! IR3 may request again at once
	out	PIC_A0,al
	sti                             ! RS-232 (and DP-RAM) may nest
	mov	bl,cl
	and	bx,*0x0F                ! the port
	cmp	bx,*NO_PORT
	jae	dp_bad
	mov	si,bx
	add	si,si
	and	cl,#0xF0                ! the kind
	cmp	cl,#MB_CHUNK
	jne	dp_1
	mov	byte ptr _rbt_seen[bx],#0
	call	take_chunk_r
	jmp	dp_out
dp_1:
	cmp	cl,#MB_ACK
	jne	dp_2
	mov	byte ptr _chunk_out[bx],#0
	jmp	dp_out
dp_2:
	cmp	cl,#MB_RESET
	jne	dp_bad
	cli
	mov	al,#1                   ! reset, the main CPU knows
	call	reset_ask_r
	jmp	dp_out
dp_bad:
	inc	word ptr [_n_badmb]
dp_out:
	cli
	ret

! Copy one chunk of a frame for the host from data[p] into the txbuf ring (the paper's
! DP-RAM_interrupt_service loop: byte by byte up to ETX or 339 bytes), then ACK it.  The chunk
! holding ETX completes the frame: it is queued for sending (step 10 from the main loop) and
! pflag[p] is freed (the reader frees it) before the ACK word.  Without room for a whole chunk
! the chunk stays in DP-RAM unacknowledged (chunk_pending) until a frame has been sent.  A port
! reset during the copy (gen[p] changed) drops it.  Any IF (kept).  Changes AX CX DX DI ES.
tc_full:
	mov	byte ptr _chunk_pending[bx],#1  ! no room: the chunk waits (the main loop retries)
	popf
	ret
.even
take_chunk_r:
	pushf
	cli
	cmp	word ptr _tx_used[si],#TXBUF_SIZE-CHUNK
	ja	tc_full
	cmp	byte ptr _tx_have[bx],#TXQ
	jae	tc_full
	mov	byte ptr _chunk_pending[bx],#0
	popf
	mov	dl,_gen[bx]             ! DL = the port's generation
	push	bx
	push	si
	mov	ax,_area[si]
	mov	di,_tx_wr[si]
	mov	bx,_txbuf[si]
	add	di,bx                   ! DI = where the chunk goes
	add	bx,#TXBUF_SIZE          ! BX = the end of the ring
	mov	si,ax                   ! SI = data[p]
	mov	ax,#DP_SEG
	mov	es,ax
	mov	cx,#CHUNK
	cld
tc_loop:
	seg	es
	lodsb
	mov	[di],al
	inc	di
	cmp	di,bx
	je	tc_wrap
tc_next:
	cmp	al,#ETX
	loopne	tc_loop
	mov	al,#0
	jne	tc_copied
	inc	al                      ! AL = 1: ETX, the frame's last chunk
tc_copied:
	neg	cx
	add	cx,#CHUNK               ! CX = bytes copied
	sub	di,bx
	add	di,#TXBUF_SIZE          ! DI = the new tx_wr
	pop	si
	pop	bx
	pushf
	cli
	cmp	dl,_gen[bx]
	jne	tc_gone                 ! the port was reset meanwhile
	mov	_tx_wr[si],di
	add	_tx_used[si],cx
	add	_tx_part[si],cx
	or	al,al
	jz	tc_ack
	mov	al,_txq_head[bx]        ! queue the frame: txq_len[p][(head + have) & (TXQ - 1)]
	add	al,_tx_have[bx]
	and	al,#TXQ-1
	xor	ah,ah
	add	ax,ax
	mov	di,si
	shl	di,1
	shl	di,1
	shl	di,1
	add	di,ax
	mov	ax,_tx_part[si]
	mov	_txq_len[di],ax
	mov	word ptr _tx_part[si],*0
	inc	byte ptr _tx_have[bx]
	mov	di,_area[si]
	mov	ax,#DP_SEG
	mov	es,ax
	seg	es
	mov	byte ptr CHUNK[di],#P_FREE      ! pflag[p]: the reader frees it before the ACK
tc_ack:
	mov	al,#MB_ACK
	or	al,bl
	call	mb_post_r
tc_gone:
	popf
	ret
tc_wrap:
	sub	di,#TXBUF_SIZE
	jmp	tc_next

! ---- port reset: asked for here, run by the main loop (hw.c port_reinit) ---------------------
! A port reset is asked for (BREAK, mailbox word 0x3p; AL = the reset_due bits: 1, or 3 to tell
! the main CPU with a 0x3p word).  A frame we have answered with EOT (step 2, being handed to the
! main CPU) is a promise of delivery: the reset is only noted and waits until its last chunk has
! been consumed (to_dpram asks again then); the port answers ENQ with NAK meanwhile.  Otherwise
! reset_now_r.  IF = 0; short, so that the handlers may ask (docs/firmware.md "Faults and the
! rule").  Changes AX, DX.
reset_ask_r:
	cmp	byte ptr _step[bx],#ST_DONE
	jne	reset_now_r
	cmp	byte ptr _reset_due[bx],#0
	jne	ra_1
	inc	word ptr _n_deferred[si]
ra_1:
	or	_reset_due[bx],al
	ret

! Ask for the reset now, whatever the step: step 4, the generation bumped (a chunk being copied
! to or from DP-RAM is dropped), the port's 82510 sources off but the tick (ger_update_r).
! AL = the reset_due bits.  IF = 0.  Changes AX, DX.
reset_now_r:
	or	_reset_due[bx],al
	cmp	byte ptr _step[bx],#ST_RESET
	je	rn_ret
	mov	byte ptr _step[bx],#ST_RESET
	inc	byte ptr _gen[bx]
	br	ger_update_r
rn_ret:
	ret

! void port_reset(int port, int notify), void port_reset_now(int port, int notify): the same for
! C, any IF.
MACRO C_RESET
_?1:
	mov	bx,sp
	mov	al,4[bx]
	or	al,6[bx]                ! notify != 0 (either byte)
	mov	bx,2[bx]
	pushf
	cli
	push	si
	push	di
	mov	si,bx
	add	si,si
	or	al,al
	mov	al,#1
	jz	?1_go
	mov	al,#3
?1_go:
	call	?2
	pop	di
	pop	si
	popf
	ret
MEND

C_RESET(port_reset,reset_ask_r)
C_RESET(port_reset_now,reset_now_r)

! ---- for the C main loop ---------------------------------------------------------------------
! void NAME(int port): BX = port, SI = 2 * port, then the routine; SI and DI kept for bcc.
MACRO C_ENTRY
_?1:
	mov	bx,sp
	mov	bx,2[bx]
	push	si
	push	di
	mov	si,bx
	add	si,si
	call	?2
	pop	di
	pop	si
	ret
MEND

C_ENTRY(tx_fill,tx_fill_r)
C_ENTRY(tx_retry,tx_retry_r)
C_ENTRY(ger_update,ger_update_r)
C_ENTRY(take_chunk,take_chunk_r)
