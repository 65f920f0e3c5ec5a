! rcsim communication firmware -- start-up, interrupt entry/exit, port and DP-RAM access.
! as86 -0 syntax.  Linked first by ld86 -0 -d -i -T 0 -D 0, so `start' is at ROM offset 0
! (physical F0000, CS = F000); the reset stub at FFFF:0000 (ROM offset FFF0) is written by mkrom:
!     FFFF0: EA <start> 00 F0        jmp far F000:start
!
! Data segment: DS = SS = ES = DATA_SEG (physical 00400).  ld86 places the initialised-data
! image right after the code, at paragraph __segoff of the image; __edata is its size and
! __end the end of BSS (both DS offsets, data linked at 0).
!
! bcc calling convention: arguments pushed right to left as words, caller pops; result in AX;
! a C function preserves BP, SI, DI (and DS, SS); AX, BX, CX, DX, ES and flags are scratch.
! bcc's code never uses ES (no string instructions), so dp_rd/dp_wr leave ES = DP_SEG; the
! interrupt entries save ES and reload it.

DATA_SEG  = 0x0040
STACK_TOP = 0x0C00
DP_SEG    = 0xD000
PIC_A0    = 0xC0
EOI_ROT   = 0xA0

.globl start
.globl __segoff
.globl __edata
.globl __end
.globl _main
.globl _rs232_isr
.globl _dpram_isr
.globl _unexpected
.globl _ticks
.globl _isr_port0
.globl _isr_port1
.globl _isr_port2
.globl _isr_dpram
.globl _isr_unexpected
.globl _inb
.globl _outb
.globl _dp_rd
.globl _dp_wr
.globl _irq_off
.globl _mul_div_up
.globl _uart_ger
.globl _irq_restore
.globl _irq_on

.text
start:
	cli
	cld
! copy the initialised data from ROM (CS + __segoff : 0) to DATA_SEG:0
	mov	ax,cs
	add	ax,#__segoff
	mov	ds,ax
	mov	ax,#DATA_SEG
	mov	es,ax
	xor	si,si
	xor	di,di
	mov	cx,#__edata
	rep
	movsb
! clear BSS (DI = __edata)
	mov	cx,#__end
	sub	cx,#__edata
	xor	al,al
	rep
	stosb
! vector table: every vector -> _isr_unexpected, then 0x20..0x23
	xor	ax,ax
	mov	es,ax
	xor	di,di
	mov	cx,#256
	mov	dx,cs
vec_fill:
	mov	ax,#_isr_unexpected
	stosw
	mov	ax,dx
	stosw
	loop	vec_fill
	seg	es
	mov	word ptr [0x80],#_isr_port0
	seg	es
	mov	word ptr [0x84],#_isr_port1
	seg	es
	mov	word ptr [0x88],#_isr_port2
	seg	es
	mov	word ptr [0x8C],#_isr_dpram
! DS = SS = ES = DATA_SEG, stack below the port buffers
	mov	ax,#DATA_SEG
	mov	ds,ax
	mov	es,ax
	mov	ss,ax
	mov	sp,#STACK_TOP
	call	_main
halt_forever:
	cli
	hlt
	jmp	halt_forever

! ---- interrupt entries ---------------------------------------------------------------------
! IR0..IR2: 82510 #0..#2.  The C handler does the work; the entry ends with the OCW2
! rotate-on-non-specific EOI and IRET.  Runs with IF = 0 throughout (no nesting).
! IR0 also carries the 1 ms tick (BRGB of 82510 #0).  Fast path for a tick alone: GIR reads
! exactly 0x2A (bank 1 selected, timer pending); read TMST (clears TBEx; BRGB reloads itself),
! count, EOI.  Anything else pending goes on to the C handler.
GIR0      = 0x84
TMST0     = 0x86
GIR_TICK  = 0x2A
_isr_port0:
	push	ax
	in	al,GIR0
	cmp	al,#GIR_TICK
	jne	port0_slow
	in	al,TMST0
	push	ds
	mov	ax,#DATA_SEG
	mov	ds,ax
	inc	word ptr [_ticks]
	pop	ds
	in	al,GIR0
	test	al,#1
	jz	port0_slow
	mov	al,#EOI_ROT
	out	PIC_A0,al
	pop	ax
	iret
port0_slow:
	xor	ax,ax
	jmp	rs232_entry
_isr_port1:
	push	ax
	mov	ax,#1
	jmp	rs232_entry
_isr_port2:
	push	ax
	mov	ax,#2
rs232_entry:
	push	bx
	push	cx
	push	dx
	push	ds
	push	es
	mov	bx,#DATA_SEG
	mov	ds,bx
	mov	es,bx
	cld
	push	ax
	call	_rs232_isr
	inc	sp
	inc	sp
	mov	al,#EOI_ROT
	out	PIC_A0,al
	pop	es
	pop	ds
	pop	dx
	pop	cx
	pop	bx
	pop	ax
	iret

! IR3: IDT7130 INT_L.  _dpram_isr reads and empties the mailbox, issues the EOI itself and
! re-enables interrupts while it copies a chunk (see docs/firmware.md), and returns with IF = 0.
_isr_dpram:
	push	ax
	push	bx
	push	cx
	push	dx
	push	ds
	push	es
	mov	ax,#DATA_SEG
	mov	ds,ax
	mov	es,ax
	cld
	call	_dpram_isr
	pop	es
	pop	ds
	pop	dx
	pop	cx
	pop	bx
	pop	ax
	iret

! Any other vector (CPU exceptions, the 8259A's spurious IR7 = vector 0x27): count and return.
! No EOI: a spurious IR7 sets no in-service bit.
_isr_unexpected:
	push	ds
	push	ax
	mov	ax,#DATA_SEG
	mov	ds,ax
	inc	word ptr [_unexpected]
	pop	ax
	pop	ds
	iret

! ---- port I/O ------------------------------------------------------------------------------
! unsigned char inb(unsigned port)
_inb:
	mov	bx,sp
	mov	dx,2[bx]
	in	al,dx
	xor	ah,ah
	ret

! void outb(unsigned port, unsigned char value)
_outb:
	mov	bx,sp
	mov	dx,2[bx]
	mov	al,4[bx]
	out	dx,al
	ret

! void uart_ger(unsigned base, unsigned char ger): GER of the 82510 at I/O `base' -- bank 0,
! GER (offset 1), back to bank 1 -- in one place and without three outb calls (the Tx FIFO and
! Tx machine interrupts are switched on and off for every frame).  Call with IF = 0.
_uart_ger:
	mov	bx,sp
	mov	dx,2[bx]
	add	dx,#4
	xor	al,al
	out	dx,al
	dec	dx
	dec	dx
	mov	al,4[bx]
	out	dx,al
	inc	dx
	inc	dx
	mov	al,#0x20
	out	dx,al
	ret

! ---- DP-RAM (left port, D000:0000..03FF) -----------------------------------------------------
! unsigned char dp_rd(unsigned offset)
_dp_rd:
	mov	bx,sp
	mov	bx,2[bx]
	mov	ax,#DP_SEG
	mov	es,ax
	seg	es
	mov	al,[bx]
	xor	ah,ah
	ret

! void dp_wr(unsigned offset, unsigned char value)
_dp_wr:
	mov	bx,sp
	mov	al,4[bx]
	mov	bx,2[bx]
	mov	dx,#DP_SEG
	mov	es,dx
	seg	es
	mov	[bx],al
	ret

! ---- arithmetic ----------------------------------------------------------------------------
! unsigned mul_div_up(unsigned a, unsigned b, unsigned c): ceil(a * b / c) with the 8086's
! 32-bit MUL and DIV (bcc's long arithmetic needs its library, which is not linked).  0xFFFF
! when the quotient does not fit in 16 bits or c = 0, so DIV never traps.  a * b + c - 1 stays
! below 2^32 (at most 0xFFFE0001 + 0xFFFE).
_mul_div_up:
	mov	bx,sp
	mov	ax,2[bx]
	mov	cx,4[bx]
	mul	cx
	mov	cx,6[bx]
	jcxz	mdu_big
	add	ax,cx
	adc	dx,#0
	sub	ax,#1
	sbb	dx,#0
	cmp	dx,cx
	jae	mdu_big
	div	cx
	ret
mdu_big:
	mov	ax,#0xFFFF
	ret

! ---- interrupt flag ------------------------------------------------------------------------
! unsigned irq_off(void): CLI, returns the previous FLAGS
_irq_off:
	pushf
	pop	ax
	cli
	ret

! void irq_restore(unsigned flags)
_irq_restore:
	mov	bx,sp
	push	word ptr 2[bx]
	popf
	ret

! void irq_on(void)
_irq_on:
	sti
	ret
