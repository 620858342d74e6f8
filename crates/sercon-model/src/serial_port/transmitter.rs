//! The transmitter: own telegrams, idle filler, test signals and the repeater's forwarded
//! signal, merged into one output line (410B §1, §2 TxD1–6, IDLE, TM0/TM1; §4.1 1H, 2H).
//!
//! Two timelines are kept: the own telegrams, and the *background* (what goes out when no own
//! telegram does: filler, a test signal, darkness or the forwarded received signal). Both are
//! merged when the chip's time passes a segment's start ([`Transmitter::release`]), so a
//! forwarded segment that an own telegram overlaps is cut (410B §1: "The slaves regenerate and
//! repeat their received data or send their own telegrams").

use sercos_wire::time::{Duration, Instant};

use super::coded_frames::{Coded, CodedFrames, Known};
use super::segment::{
    FrameHint, LineSegment, LineSignal, Shared, drop_in_line, drop_parts_in_line,
};
use crate::chip::earliest;
use crate::first_queue::FirstQueue;

/// An own telegram placed on the transmitter's timeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Placed {
    /// When the first bit (of the sync word, or of the opening flag) starts.
    pub(crate) start: Instant,
    /// When the last bit of the closing flag has left.
    pub(crate) end: Instant,
}

/// A background segment queued, and whether it is a forwarded copy the line's user carries
/// itself (not released as output when `forward_output` is off).
#[derive(Debug, Clone)]
struct Queued {
    seg: LineSegment,
    carried: bool,
}

/// An own telegram queued, encoded when it is released (then the line's level before its
/// first bit is known, so the bits are produced once, never inverted afterwards).
#[derive(Debug, Clone)]
struct Own {
    start: Instant,
    bit_time: Duration,
    /// Send the pre-frame sync word first (1H.8 PRESYNC).
    presync: bool,
    /// ADR and data as remembered: shared, or coded before (its hint, `CodedFrames::coded`).
    telegram: Known,
    /// Line bits (sync word, flags, stuffed data and FCS).
    len: u64,
}

impl Own {
    /// When its last bit ends.
    fn end(&self) -> Instant {
        self.start
            .saturating_add(self.bit_time.saturating_mul(self.len))
    }
}

/// The transmitter's timelines.
#[derive(Debug, Clone, Default)]
pub(crate) struct Transmitter {
    /// Own telegrams not yet released, by start: the first in place (a node has one queued
    /// at a time, usually: a ring slave its AT), the others behind it inline (a master
    /// queues several a cycle).
    own: FirstQueue<Own, true>,
    /// Background segments not yet released, by start: the first in place (on a ring
    /// slave, the carried MST copy, usually alone, with the MDT copy in `tail`).
    background: FirstQueue<Queued>,
    /// A carried copy queued right after the carried copy that is the background's only
    /// entry (an intact ring's MDT copy after its MST copy), kept here instead of a queue
    /// entry of its own, with the inversion it is followed with by the line's level at the
    /// entry's start (index 0: low, 1: high), chained over that entry (spec-notes "Merged
    /// carried copies"). Any other push, or a release that does not follow both, puts it
    /// into the queue first ([`Transmitter::split_merged`]).
    tail: Option<(LineSegment, [bool; 2])>,
    /// How many of `background` are not carried (released as output when their time
    /// comes): asked by [`Transmitter::sole_own`] once per own telegram, kept at every
    /// change of the queue instead of a walk of it.
    uncarried: usize,
    /// The background segment in effect (the last one whose start has passed), as queued,
    /// unless `last_is_bg` says it is `last_out` (then it is not copied at its release).
    bg_active: Option<LineSegment>,
    /// `last_out` is the background segment in effect, released (or followed) as queued,
    /// not inverted (a followed copy's inversion is `last_inv`).
    last_is_bg: bool,
    /// The own telegram released last ends here; until then the background is shadowed.
    own_until: Instant,
    /// After an own telegram, the background is resumed at this instant.
    resume_at: Option<Instant>,
    /// The earliest of the first own telegram's start, the first background segment's start
    /// and `resume_at`, kept up to date by every change of those: asked on every turn of an
    /// event loop, it is then a load, not two queue fronts.
    next_release: Option<Instant>,
    /// The output segment released last, without its hint (only its levels are asked for);
    /// for a carried copy, the copy as queued (its levels inverted when `last_inv`).
    last_out: Option<LineSegment>,
    /// The line's levels are those of `last_out` inverted: a carried copy followed from the
    /// other level than its own (`Transmitter::follow`), kept as queued, not inverted.
    last_inv: bool,
    /// Released segments the simulation has not taken yet.
    released: Vec<LineSegment>,
    /// End of the last own telegram queued.
    busy_until: Instant,
    /// The bits of the telegrams sent lately.
    coded: CodedFrames,
    /// Own telegrams carry the filler resumed after them ([`LineSegment::then_filler`]).
    pub(crate) implied_filler: bool,
    /// Forwarded copies of the received signal are not released (`Chip::set_forward_output`):
    /// they are followed (line level, what resumes after an own telegram) but not sent.
    pub(crate) carried_forwarding: bool,
    /// The resume at `resume_at` is the filler the last own telegram implies: it sends
    /// nothing (unless the background changes first).
    silent_resume: bool,
    /// The last segment released is an own telegram with `then_filler`: anything else in
    /// its place at `resume_at` must be said (a steady hold if nothing else is).
    implied_open: bool,
}

impl Own {
    /// This telegram coded on a line at light level `level` before its first bit (its bits
    /// and hint, `CodedFrames::coded`) and the end of its last bit; `None` when it cannot be
    /// encoded.
    // Inlined at every call: with the release's second own-telegram turn
    // (`Transmitter::release_merged_then_own`) LLVM kept it out of line, which cost more
    // than that turn saves.
    #[inline(always)]
    fn coded(self, level: bool, coded: &mut CodedFrames) -> Option<(Coded, Instant)> {
        let end = self.end();
        let c = coded.coded(self.telegram, self.presync, self.len, level)?;
        // What `LineSegment::end` gives for the segment of these bits (`len` is their
        // number, `CodedFrames::lookup`): found without the load of the bits.
        debug_assert_eq!(
            end,
            self.start
                .saturating_add(self.bit_time.saturating_mul(c.bits.len()))
        );
        Some((c, end))
    }
}

impl Transmitter {
    /// Whether an own telegram queued before is still going out at `at` (it ends after
    /// `at`): a telegram handed over then would wait behind it.
    pub(crate) fn own_busy_at(&self, at: Instant) -> bool {
        at < self.busy_until
    }

    /// Queues an own telegram (ADR and data) at `at`, or right after the own telegram being
    /// sent if that ends later; `None` when the telegram cannot be encoded (empty or longer
    /// than the line layer allows).
    pub(crate) fn transmit(
        &mut self,
        at: Instant,
        bit_time: Duration,
        presync: bool,
        telegram: &[u8],
    ) -> Option<Placed> {
        let start = at.max(self.busy_until);
        if telegram.is_empty() || telegram.len() > sercos_wire::line::MAX_TELEGRAM_BYTES {
            // Not encodable (sercos-wire's `EncodeError`): nothing is sent.
            return None;
        }
        let (telegram, len) = self.coded.lookup(telegram, presync);
        let own = Own {
            start,
            bit_time,
            presync,
            telegram,
            len,
        };
        let end = own.end();
        self.own.push_back(own);
        self.busy_until = end;
        // Own telegrams are queued in order of start (each at or after the end of the one
        // before): the first own start is as it was, or this one when none was queued;
        // either way the next release is the earlier of the one kept and this start.
        self.next_release = earliest(self.next_release, Some(start));
        debug_assert_eq!(self.next_release, self.compute_next_release());
        Some(Placed { start, end })
    }

    /// Puts `seg` on the background timeline; background segments queued to start after it
    /// are dropped (it replaces them).
    pub(crate) fn push_background(&mut self, seg: LineSegment) {
        self.queue_background(seg, false);
    }

    /// [`Transmitter::push_background`] for the repeater's copy of the received signal
    /// (410B §1): not released as output when forwarded copies are carried by the user.
    pub(crate) fn push_forwarded(&mut self, seg: LineSegment) {
        let carried = self.carried_forwarding;
        self.queue_background(seg, carried);
    }

    /// [`Transmitter::push_forwarded`] of the repeater's copy of the received `seg` with
    /// carried forwarding on and the polarities alike (410B §1: regenerated, so not
    /// distorted, `latency_bits` bit times later; no hint, "Followed copies"), built in
    /// place. The two usual cases inline (an empty queue, and the merge of
    /// [`Transmitter::tail`]); the rest as [`Transmitter::queue_background`].
    /// Debug builds compare the transmitter with one given the copy the general way.
    #[inline(always)]
    ///
    /// `follows`: the start of the receiver's last segment when `seg` was taken to the level
    /// that segment leaves the line at (`Chip::line_input_at_level`, a bits segment).
    pub(crate) fn push_carried(
        &mut self,
        seg: &LineSegment,
        latency_bits: u64,
        follows: Option<Instant>,
    ) {
        debug_assert!(self.carried_forwarding);
        #[cfg(debug_assertions)]
        let general = {
            let mut general = self.clone();
            let latency = seg.bit_time.saturating_mul(latency_bits);
            general.push_forwarded(LineSegment {
                distorted: false,
                ..seg.without_hint().delayed(latency)
            });
            format!("{general:?}")
        };
        self.push_carried_in_place(seg, latency_bits, follows);
        #[cfg(debug_assertions)]
        debug_assert_eq!(
            general,
            format!("{self:?}"),
            "a carried copy built in place differs from the general push"
        );
    }

    /// [`Transmitter::push_carried`] without its check.
    #[inline(always)]
    fn push_carried_in_place(
        &mut self,
        seg: &LineSegment,
        latency_bits: u64,
        follows: Option<Instant>,
    ) {
        let latency = seg.bit_time.saturating_mul(latency_bits);
        let start = seg.start.saturating_add(latency);
        let copy = || LineSegment {
            start,
            bit_time: seg.bit_time,
            signal: seg.signal.clone(),
            level_before: seg.level_before,
            hint: None,
            distorted: false,
            then_filler: seg.then_filler,
        };
        if self.tail.is_none() {
            if self.background.is_empty() {
                // What `queue_background` does with nothing queued: the copy is the
                // queue, and the next release the earlier of the one kept and its start.
                self.background.push_back(Queued {
                    seg: copy(),
                    carried: true,
                });
                self.next_release = earliest(self.next_release, Some(start));
                debug_assert_eq!(self.next_release, self.compute_next_release());
                debug_assert_eq!(self.uncarried, self.count_uncarried());
                return;
            }
            if self.background.is_single()
                && let Some(b) = self.background.back()
                && b.carried
                && b.seg.start < start
            {
                // The merge (`queue_background`). When the queued copy is the copy of the
                // receiver's last segment and `seg` starts from the level that one leaves
                // (410B §1 repeater: the copy is the received signal, delayed), the level
                // the copy leaves at `start` is `seg`'s level before: the chained inversion
                // is the copy's own.
                let inv = if follows.is_some_and(|last| last.saturating_add(latency) == b.seg.start)
                    && matches!(seg.signal, LineSignal::Bits(_))
                {
                    let inv = single_inv(&b.seg);
                    debug_assert_eq!(inv, chained_inversion(&b.seg, start, seg));
                    inv
                } else {
                    chained_inversion(&b.seg, start, seg)
                };
                // `tail` is empty (above): set without a drop of what it held (no drop
                // glue's call; `get_or_insert_with` went out of line, a plain assignment
                // keeps the drop). What is forgotten is that `None`: nothing leaks.
                let before = self.tail.replace((copy(), inv));
                debug_assert!(before.is_none(), "the merged copy's place was empty");
                std::mem::forget(before);
                debug_assert_eq!(self.next_release, self.compute_next_release());
                return;
            }
        }
        self.queue_background(copy(), true);
    }

    fn queue_background(&mut self, seg: LineSegment, carried: bool) {
        let start = seg.start;
        if self.tail.is_some() {
            self.split_merged();
        } else if carried
            && self.background.is_single()
            && let Some(b) = self.background.back()
            && b.carried
            && b.seg.start < start
        {
            // A carried copy after a carried copy (410B §1 repeater): its inversion chained
            // from the level the one before leaves at its start (`Transmitter::skip_followed`;
            // spec-notes "Merged carried copies").
            let inv = chained_inversion(&b.seg, start, &seg);
            self.tail = Some((seg, inv));
            debug_assert_eq!(self.next_release, self.compute_next_release());
            return;
        }
        while self.background.back().is_some_and(|b| b.seg.start >= start) {
            if let Some(b) = self.background.pop_back() {
                self.uncarried = self.uncarried.saturating_sub(usize::from(!b.carried));
            }
        }
        self.background.push_back(Queued { seg, carried });
        self.uncarried += usize::from(!carried);
        // The background's front is as it was, or this segment (every segment it replaced
        // starts at or after it): either way the next release is the earlier of the one kept
        // and its start.
        self.next_release = earliest(self.next_release, Some(start));
        debug_assert_eq!(self.next_release, self.compute_next_release());
        debug_assert_eq!(self.uncarried, self.count_uncarried());
    }

    /// Puts the merged copy ([`Transmitter::tail`]) into the queue: the queue of separate
    /// copies.
    #[cold]
    fn split_merged(&mut self) {
        if let Some((seg, _)) = self.tail.take() {
            self.background.push_back(Queued { seg, carried: true });
        }
    }

    /// The transmitter as the queue of separate copies leaves it (debug comparisons).
    #[cfg(debug_assertions)]
    fn separate(&self) -> Transmitter {
        let mut t = self.clone();
        t.split_merged();
        t
    }

    /// [`Transmitter::uncarried`] from the queue.
    fn count_uncarried(&self) -> usize {
        self.background.iter().filter(|q| !q.carried).count()
    }

    /// The light level of the output line at `t` (at or after the last release).
    // Inlined at every call: with the release's second own-telegram turn
    // (`Transmitter::release_merged_then_own`) LLVM kept it out of line, which cost more
    // than that turn saves.
    #[inline(always)]
    pub(crate) fn level_at(&self, t: Instant) -> bool {
        // An inverted segment's level is the other one at every instant (bits, dark and
        // light swapped, filler from the other level): `LineSegment::inverted`.
        self.last_out
            .as_ref()
            .is_some_and(|s| s.level_at(t) != self.last_inv)
    }

    /// The instant the next output segment starts, if one is queued.
    pub(crate) fn next_release_at(&self) -> Option<Instant> {
        debug_assert_eq!(self.next_release, self.compute_next_release());
        self.next_release
    }

    /// [`Transmitter::next_release_at`] from the queues.
    fn compute_next_release(&self) -> Option<Instant> {
        let (own, background) = self.fronts();
        self.next_of(own, background)
    }

    /// The starts of the first own telegram and of the first background segment queued.
    fn fronts(&self) -> (Option<Instant>, Option<Instant>) {
        (
            self.own.front().map(|s| s.start),
            self.background.front().map(|q| q.seg.start),
        )
    }

    /// The next release given the queues' [`Transmitter::fronts`]: the earliest of them and
    /// the resume.
    fn next_of(&self, own: Option<Instant>, background: Option<Instant>) -> Option<Instant> {
        earliest(earliest(own, background), self.resume_at)
    }

    /// The instant the next own output starts: an own telegram, or the background resumed
    /// after one (not a queued background segment, nor a resume the last own telegram's
    /// implied filler stands for).
    pub(crate) fn next_own_release_at(&self) -> Option<Instant> {
        let resume = self.resume_at.filter(|r| !self.resume_is_silent(*r));
        match (self.own.front().map(|s| s.start), resume) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Whether the resume at `at` will send nothing: the last own telegram implies the
    /// filler it resumes, and no queued background segment starts before it (one would be
    /// shadowed and resumed instead).
    fn resume_is_silent(&self, at: Instant) -> bool {
        self.silent_resume && self.background.front().is_none_or(|b| b.seg.start >= at)
    }

    /// The one own telegram queued, `(start, end, bit time)`, when nothing else will be
    /// released around it: no background segment queued and any resume after it silent.
    #[inline(always)]
    pub(crate) fn sole_own(&self) -> Option<(Instant, Instant, Duration)> {
        debug_assert_eq!(self.uncarried, self.count_uncarried());
        if !self.own.is_single() || !self.released.is_empty() || self.uncarried != 0 {
            return None;
        }
        if self.resume_at.is_some_and(|r| !self.resume_is_silent(r)) {
            return None;
        }
        let own = self.own.front()?;
        Some((own.start, own.end(), own.bit_time))
    }

    /// The earliest of [`Transmitter::next_own_release_at`] and the first of
    /// [`Transmitter::background_starts`]: without a walk of the queue when every queued
    /// background segment is carried (`uncarried`).
    pub(crate) fn next_uncarried_release_at(&self) -> Option<Instant> {
        debug_assert_eq!(self.uncarried, self.count_uncarried());
        let own = self.next_own_release_at();
        if self.uncarried == 0 {
            return own;
        }
        earliest(own, self.background_starts().next())
    }

    /// Starts of the queued background segments that will be released as output
    /// (forwarded input unless carried, filler), in order.
    pub(crate) fn background_starts(&self) -> impl Iterator<Item = Instant> + '_ {
        self.background
            .iter()
            .filter(|q| !q.carried)
            .map(|q| q.seg.start)
    }

    /// Releases every output segment that starts at or before `now`.
    ///
    /// Takes two short paths of the general loop ([`Transmitter::release_with`]); debug
    /// builds run the general loop on a copy and compare the whole state.
    pub(crate) fn release(&mut self, now: Instant) {
        self.release_checked(now, "the release's short paths", |t| {
            t.release_with::<true>(now)
        });
    }

    /// [`Transmitter::release`] for a take that mostly finds the one own telegram queued
    /// and nothing else (a ring master's: its MST or MDT, 410B §4.1 0CH, §4.2.1):
    /// [`Transmitter::release_sole_own`] first, the loop after it when that does not finish
    /// the release. Debug builds run the general loop on a copy and compare the whole state.
    pub(crate) fn release_own_first(&mut self, now: Instant) {
        self.release_checked(now, "the release of a sole own telegram", |t| {
            if !t.release_sole_own(now) {
                t.release_with::<true>(now);
            }
        });
    }

    /// Runs `release`, a release up to `now` by short paths (`what`); debug builds run the
    /// general loop ([`Transmitter::release_with`] without them) on a copy and compare the
    /// whole state.
    #[inline(always)]
    fn release_checked(&mut self, now: Instant, what: &str, release: impl FnOnce(&mut Self)) {
        #[cfg(debug_assertions)]
        let general = {
            let mut general = self.separate();
            general.release_with::<false>(now);
            format!("{general:?}")
        };
        #[cfg(not(debug_assertions))]
        let _ = (now, what);
        release(self);
        #[cfg(debug_assertions)]
        debug_assert_eq!(
            general,
            format!("{:?}", self.separate()),
            "{what}: not as the general loop leaves it"
        );
    }

    /// [`Transmitter::release`]; `SHORT`: with its short paths (a run of carried copies
    /// followed as one, the silent resume after an own telegram taken with it), which leave
    /// the same state as the general loop's turns one by one.
    fn release_with<const SHORT: bool>(&mut self, now: Instant) {
        if SHORT && self.release_merged_then_own(now) && self.own.is_empty() {
            // Nothing left queued (the background's only entry and the copy merged after
            // it followed, the one own telegram released) and no resume pending (its
            // silent resume taken with it): the loop would find nothing due.
            if self.resume_at.is_none() {
                debug_assert!(self.background.is_empty() && self.tail.is_none());
                self.next_release = None;
                debug_assert_eq!(self.next_release, self.compute_next_release());
                return;
            }
        }
        self.release_loop::<SHORT>(now);
    }

    /// [`Transmitter::release_with`]'s general loop, out of the line of its short path (a
    /// ring slave's take is that path alone, and the loop's frame and saved registers are
    /// not needed there).
    #[inline(never)]
    fn release_loop<const SHORT: bool>(&mut self, now: Instant) {
        loop {
            // The queues' fronts once per turn.
            let (own_at, bg_at) = self.fronts();
            let Some(t) = self.next_of(own_at, bg_at).filter(|t| *t <= now) else {
                break;
            };
            if own_at == Some(t) {
                let Some(own) = self.own.pop_front() else {
                    break;
                };
                self.release_own::<SHORT>(own, t, now);
            } else if bg_at == Some(t) {
                if let Some((tail, tail_inv)) = self.tail.take() {
                    // The background's only entry and the copy merged after it, followed as
                    // one when the release loop would follow both: the first past the last
                    // own telegram's end, the second at or before `now` and before the next
                    // own telegram (which wins a tie).
                    if self.background.is_single()
                        && t >= self.own_until
                        && tail.start <= now
                        && own_at.is_none_or(|o| tail.start < o)
                    {
                        self.background.clear();
                        self.resume_at = None;
                        self.silent_resume = false;
                        let invert = tail_inv[usize::from(self.level_at(t))];
                        self.follow_checked(tail, invert, "a merged copy");
                        continue;
                    }
                    // Not followed as one (or a resumed rest before it): taken copy by copy.
                    self.tail = Some((tail, tail_inv));
                    self.split_merged();
                }
                let Some(Queued { seg, carried }) = self.background.pop_front() else {
                    break;
                };
                self.uncarried = self.uncarried.saturating_sub(usize::from(!carried));
                if t >= self.own_until {
                    // It takes the resume's place (an implied filler is cut at once).
                    self.resume_at = None;
                    self.silent_resume = false;
                    // A forwarded telegram after an own one continues from the level the
                    // line is at, as own telegrams do (NRZI decodes it the same; without
                    // this its first flag bit would be lost downstream).
                    let invert = matches!(seg.signal, LineSignal::Bits(_))
                        && seg.level_before != self.level_at(t);
                    if carried {
                        // A copy the user carries is only followed, not released.
                        let (seg, invert) = if SHORT {
                            self.skip_followed(seg, invert, own_at, now)
                        } else {
                            (seg, invert)
                        };
                        self.follow_checked(seg, invert, "a followed copy");
                    } else if invert {
                        self.bg_active = Some(seg.clone());
                        self.emit(seg.inverted());
                    } else {
                        self.bg_active = None;
                        self.emit(seg);
                        self.last_is_bg = true;
                    }
                } else {
                    // Shadowed by the own telegram being sent: resumed instead.
                    self.bg_active = Some(seg);
                    self.silent_resume = false;
                }
            } else {
                self.resume_at = None;
                if std::mem::take(&mut self.silent_resume) {
                    // The own telegram's implied filler is this very filler: the background
                    // it resumes has not changed since (any change clears `silent_resume`),
                    // and `resumes_filler` found it filler from here on. Nothing to send.
                    debug_assert!(
                        self.bg_active
                            .as_ref()
                            .and_then(|bg| bg.from_instant(t))
                            .is_some_and(|r| r.start == t
                                && matches!(r.signal, LineSignal::Filler))
                    );
                    continue;
                }
                let rest = self.bg_active.as_ref().and_then(|bg| bg.from_instant(t));
                let mut sent = false;
                if let Some(mut rest) = rest {
                    if rest.start > t {
                        // A bits segment resumes at its first bit boundary after `t`: it is
                        // released when time reaches it, so that the output stays in order of
                        // start, unless the next background segment replaces it first.
                        if self
                            .background
                            .front()
                            .is_none_or(|b| b.seg.start > rest.start)
                        {
                            // Not a copy of the input any more: released as output.
                            self.background.push_front(Queued {
                                seg: rest,
                                carried: false,
                            });
                            self.uncarried += 1;
                        }
                    } else {
                        if !matches!(rest.signal, LineSignal::Bits(_)) {
                            // A steady signal starts afresh from the level the own telegram
                            // left.
                            rest.level_before = self.level_at(t);
                        }
                        self.emit(rest);
                        sent = true;
                    }
                }
                if !sent && self.implied_open {
                    // The own telegram said filler follows; the line keeps its last level
                    // instead: a segment of no bits says so (a steady hold; spec-notes
                    // "Implied filler").
                    let hold = LineSegment::bits(
                        t,
                        self.last_out
                            .as_ref()
                            .map_or(Duration::ZERO, |l| l.bit_time),
                        sercos_wire::line::BitVec::new(),
                        self.level_at(t),
                    );
                    self.emit(hold);
                }
            }
        }
        self.next_release = self.compute_next_release();
    }

    /// The release loop's turn for the own telegram `own` due at `t`, popped from the queue.
    #[inline(always)]
    fn release_own<const SHORT: bool>(&mut self, own: Own, t: Instant, now: Instant) {
        // The NRZI coder continues from the level the line is at.
        let level = self.level_at(t);
        let (start, bit_time) = (own.start, own.bit_time);
        let Some((c, end)) = own.coded(level, &mut self.coded) else {
            return;
        };
        if self.last_is_bg {
            // The background in effect is about to be shadowed: keep it for the
            // resume (its start has passed, so the hint it lost is not needed).
            self.bg_active = self.last_out.take();
            self.last_inv = false;
        }
        self.own_until = end;
        self.resume_at = Some(end);
        // The background resumed after it is plain filler of the same bit time
        // (410B §1: a master's idle filler, or the filler a slave repeats, "or send
        // their own telegrams"): it travels with the telegram (spec-notes "Implied
        // filler"), and the resume sends nothing unless that changes.
        self.silent_resume = self.implied_filler
            && self
                .bg_active
                .as_ref()
                .is_some_and(|bg| resumes_filler(bg, end, bit_time));
        let open = self.silent_resume;
        self.emit_own(start, bit_time, c, level);
        if SHORT && open && self.own_until <= now && self.resume_stays_silent() {
            // The silent resume (spec-notes "Implied filler") is due: what its turn
            // does, without the turn.
            self.resume_at = None;
            self.silent_resume = false;
        }
    }

    /// The loop's turns when the one own telegram queued is all there is (a master's take).
    #[inline(always)]
    fn release_sole_own(&mut self, now: Instant) -> bool {
        let Some(t) = self.own.front().map(|o| o.start) else {
            return false;
        };
        if !self.own.is_single()
            || !self.background.is_empty()
            || self.tail.is_some()
            || t > now
            || self.resume_at.is_some_and(|r| !self.silent_resume || r > t)
        {
            return false;
        }
        self.resume_at = None;
        self.silent_resume = false;
        let Some(own) = self.own.pop_front() else {
            return false;
        };
        self.release_own::<true>(own, t, now);
        match self.resume_at {
            Some(r) if r > now => {
                self.next_release = Some(r);
                debug_assert_eq!(self.next_release, self.compute_next_release());
                true
            }
            _ => false,
        }
    }

    /// The release loop's first two turns when they are a merged follow and then the first
    /// own telegram (a ring slave's take: its MST and MDT copies, then its AT), done as
    /// one: the background's only entry and the copy merged after it
    /// ([`Transmitter::tail`]) start before the own telegram (which would win a tie), the
    /// first past the last own telegram's end, no resume pending, and the own telegram
    /// starts at or before `now`. The merged copy is followed (410B §1 repeater; spec-notes
    /// "Merged carried copies") and at once shadowed by the own telegram, which is coded
    /// from the level it leaves and keeps it for the resume, as the two turns leave it;
    /// the loop goes on from there. Debug builds compare every release with the general
    /// loop ([`Transmitter::release`]).
    #[inline(always)]
    fn release_merged_then_own(&mut self, now: Instant) -> bool {
        let (Some(own), Some(first), Some((tail, tail_inv))) = (
            self.own.front(),
            self.background.front(),
            self.tail.as_ref(),
        ) else {
            return false;
        };
        let (o, t0) = (own.start, first.seg.start);
        // The first copy starts before the merged one (the merge's condition), so before
        // the own telegram too.
        debug_assert!(t0 < tail.start);
        if self.resume_at.is_some()
            || !self.background.is_single()
            || o > now
            || tail.start >= o
            || t0 < self.own_until
        {
            return false;
        }
        // The follow's inversion by the line's level at the first copy's start, then the
        // level the merged copy leaves at the own telegram's start (the NRZI coder
        // continues from it). Found in place: the copies are moved once, at the end.
        let invert = tail_inv[usize::from(self.level_at(t0))];
        let level = tail.level_at(o) != invert;
        let Some(own) = self.own.pop_front() else {
            return false;
        };
        // The first copy, the queue's only entry (one pop, not a truncate's loop).
        drop(self.background.pop_front());
        let (start, bit_time) = (own.start, own.bit_time);
        let Some((c, own_until)) = own.coded(level, &mut self.coded) else {
            // Not encodable: the follow alone, as its turn leaves it.
            self.resume_at = None;
            self.silent_resume = false;
            if let Some((tail, _)) = self.tail.take() {
                self.follow(tail, invert);
            }
            return true;
        };
        // The followed copy is the background in effect, shadowed now: kept for the resume
        // as queued (`bg_active`), the line's last segment the own telegram (`emit`).
        self.own_until = own_until;
        self.resume_at = Some(own_until);
        // 410B §1: the filler the slave repeats resumes after its own telegram (spec-notes
        // "Implied filler"), as in the loop's own turn.
        self.silent_resume = self.implied_filler
            && self
                .tail
                .as_ref()
                .is_some_and(|(tail, _)| resumes_filler(tail, own_until, bit_time));
        // The merged copy moved into place (it is there: checked above).
        if let Some((tail, _)) = self.tail.take()
            && let Some((signal, hint)) = write_over(&mut self.bg_active, tail)
        {
            drop_parts_in_line(signal, hint);
        }
        let open = self.silent_resume;
        self.emit_own(start, bit_time, c, level);
        if open && own_until <= now && self.resume_stays_silent() {
            self.resume_at = None;
            self.silent_resume = false;
        }
        true
    }

    /// Whether the resume at `own_until` is taken as a silent one by the release loop
    /// whatever comes before it: no background segment starts before it (one would be
    /// shadowed and resumed instead). A background segment at `own_until` wins the tie and
    /// clears the resume itself, as does an own telegram (which never starts earlier: it
    /// is queued after the one before, `Transmitter::transmit`).
    fn resume_stays_silent(&self) -> bool {
        let at = self.own_until;
        debug_assert!(self.own.front().is_none_or(|o| o.start >= at));
        self.background.front().is_none_or(|b| b.seg.start >= at)
    }

    /// The last of the carried copies that the release loop would follow one after the
    /// other from `seg` on (with `invert`, its inversion): each next background front that
    /// is carried, starts at or before `now` and before the next own telegram (`own_at`;
    /// an own telegram wins a tie), with its inversion found from the level the copy before
    /// leaves (410B §1 repeater; spec-notes "Followed copies"). The copies passed over are
    /// dropped: a follow keeps nothing of the copy before it but that level. Called with
    /// the resume cleared and `seg` past the last own telegram's end, which then holds for
    /// every later copy too.
    fn skip_followed(
        &mut self,
        mut seg: LineSegment,
        mut invert: bool,
        own_at: Option<Instant>,
        now: Instant,
    ) -> (LineSegment, bool) {
        debug_assert!(self.resume_at.is_none() && seg.start >= self.own_until);
        while let Some(next) = self.background.front()
            && next.carried
            && next.seg.start <= now
            && own_at.is_none_or(|o| next.seg.start < o)
        {
            let level = seg.level_at(next.seg.start) != invert;
            invert =
                matches!(next.seg.signal, LineSignal::Bits(_)) && next.seg.level_before != level;
            let Some(q) = self.background.pop_front() else {
                break;
            };
            seg = q.seg;
        }
        (seg, invert)
    }

    /// [`Transmitter::follow`]; debug builds check the result against the general path's
    /// follow of the same copy (`what` names it in the message).
    #[inline(always)]
    fn follow_checked(&mut self, seg: LineSegment, invert: bool, what: &str) {
        #[cfg(debug_assertions)]
        let expected = self.followed_general(&seg, invert);
        self.follow(seg, invert);
        #[cfg(debug_assertions)]
        debug_assert_eq!(
            expected,
            self.followed_digest(),
            "{what} differs from the general path's"
        );
        #[cfg(not(debug_assertions))]
        let _ = what;
    }

    /// Follows a copy the user carries that starts when no own telegram shadows it: it
    /// becomes the line's last segment and the background in effect, as queued; `invert`:
    /// the line is at the other level than its `level_before`, so its levels are inverted
    /// (410B §1 repeater; spec-notes "Followed copies"). What the general path
    /// ([`Transmitter::followed_general`]) keeps, without the inverted bits, the copy for
    /// the resume and the hint.
    fn follow(&mut self, seg: LineSegment, invert: bool) {
        self.bg_active = None;
        self.last_out = Some(seg);
        self.last_inv = invert;
        self.last_is_bg = true;
        self.implied_open = false;
    }

    /// What the general path leaves after following `seg` ([`Transmitter::follow`]): the
    /// copy kept for the resume, and, as the line's last segment, the copy without its hint,
    /// inverted when the line is at the other level (a check in debug builds).
    #[cfg(debug_assertions)]
    fn followed_general(&self, seg: &LineSegment, invert: bool) -> String {
        let mut general = self.clone();
        let seg = seg.clone();
        if invert {
            general.bg_active = Some(seg.clone());
            general.last_out = Some(LineSegment {
                hint: None,
                ..seg.inverted()
            });
            general.last_is_bg = false;
        } else {
            general.bg_active = None;
            general.last_out = Some(LineSegment { hint: None, ..seg });
            general.last_is_bg = true;
        }
        general.last_inv = false;
        general.implied_open = false;
        general.followed_digest()
    }

    /// What the state after a followed copy says for every later use: the line's levels
    /// (its last segment, inversion applied), the background resumed after an own telegram
    /// (`bg_active`, or `last_out` while it is the background), without hints (never read
    /// from a copy that is only followed: a resume cuts it, `LineSegment::from_instant`).
    #[cfg(debug_assertions)]
    fn followed_digest(&self) -> String {
        let bare = LineSegment::without_hint;
        let line = self.last_out.as_ref().map(|s| {
            if self.last_inv {
                bare(s).inverted()
            } else {
                bare(s)
            }
        });
        let bg = if self.last_is_bg {
            self.last_out.as_ref().map(bare)
        } else {
            self.bg_active.as_ref().map(bare)
        };
        format!(
            "{line:?} {bg:?} {} {:?} {} {:?}",
            self.implied_open, self.resume_at, self.silent_resume, self.own_until
        )
    }

    fn emit(&mut self, seg: LineSegment) {
        // Stored first, then copied from where it lies: `seg` was built just before the
        // call, and reading it twice (for the copy and for the store) waited twice on the
        // stores that built it (store forwarding; `docs/performance.md`, "Controller pair").
        self.released.push(seg);
        // The segment it replaces as the line's last, dropped in line (`drop_in_line`).
        let last = self.released.last().map(LineSegment::without_hint);
        if let Some(before) = std::mem::replace(&mut self.last_out, last) {
            drop_in_line(before);
        }
        self.last_inv = false;
        self.last_is_bg = false;
        self.implied_open = false;
    }

    /// [`Transmitter::emit`] of an own telegram's segment, from its parts: its first bit at
    /// `start`, coded (`c`) from the line's level `level_before` (410B §2 TxD: the NRZI
    /// coder continues from the level the line is at), with the filler resumed after it
    /// when the resume is silent (`then_filler`, spec-notes "Implied filler"), which
    /// leaves the implied filler open. The segment is written where it is kept, from
    /// registers: built on the stack and copied, its 16-byte loads waited on the narrower
    /// stores that built it (docs/performance.md, "Session 32"). Debug builds
    /// compare the result with `emit` of the segment built whole.
    #[inline(never)]
    fn emit_own(&mut self, start: Instant, bit_time: Duration, c: Coded, level_before: bool) {
        let then_filler = self.silent_resume;
        #[cfg(debug_assertions)]
        let general = {
            let mut general = self.clone();
            general.emit(LineSegment {
                start,
                bit_time,
                signal: LineSignal::Bits(c.bits.clone()),
                level_before,
                hint: Some(c.hint.clone()),
                distorted: false,
                then_filler,
            });
            general.implied_open = then_filler;
            format!("{general:?}")
        };
        // The line's last segment, without its hint.
        let before = write_over(
            &mut self.last_out,
            LineSegment {
                start,
                bit_time,
                signal: LineSignal::Bits(c.bits.clone()),
                level_before,
                hint: None,
                distorted: false,
                then_filler,
            },
        );
        let seg = || LineSegment {
            start,
            bit_time,
            signal: LineSignal::Bits(c.bits),
            level_before,
            hint: Some(c.hint),
            distorted: false,
            then_filler,
        };
        if self.released.len() < self.released.capacity() {
            // Room for it: built in its slot (the push cannot grow, so nothing holds it on
            // the stack while a growth could unwind).
            self.released.push(seg());
        } else {
            push_growing(&mut self.released, seg());
        }
        if let Some((signal, hint)) = before {
            drop_parts_in_line(signal, hint);
        }
        self.last_inv = false;
        self.last_is_bg = false;
        self.implied_open = then_filler;
        #[cfg(debug_assertions)]
        debug_assert_eq!(
            general,
            format!("{self:?}"),
            "an own segment emitted from its parts differs from emit's"
        );
    }

    /// Whether no released segment waits to be taken.
    pub(crate) fn nothing_released(&self) -> bool {
        self.released.is_empty()
    }

    /// Moves the released segments to the end of `out`.
    pub(crate) fn take_released(&mut self, out: &mut Vec<LineSegment>) {
        if self.released.is_empty() {
            return;
        }
        if out.is_empty() {
            // The usual case (a simulation drains `out` after each take): the two buffers
            // trade places, both keep their capacity and nothing is copied (`append` calls
            // memcpy, ≈ 3 % of the pair bench's time).
            std::mem::swap(out, &mut self.released);
            return;
        }
        out.append(&mut self.released);
    }
}

/// `out.push(seg)` when `out` has to grow (out of the hot path's line: the hot path pushes
/// only into room it has checked, `Transmitter::emit_own`).
#[cold]
#[inline(never)]
fn push_growing(out: &mut Vec<LineSegment>, seg: LineSegment) {
    out.push(seg);
}

/// Puts `seg` in `slot`, written over the segment there field by field, and returns that
/// segment's shared parts (signal and hint) to be dropped: moved whole, the two segments
/// went through the stack.
#[inline(always)]
fn write_over(
    slot: &mut Option<LineSegment>,
    seg: LineSegment,
) -> Option<(LineSignal, Option<Shared<FrameHint>>)> {
    let Some(l) = slot else {
        // Nothing to write over (only before the first release): the segment moved in.
        *slot = Some(seg);
        return None;
    };
    let LineSegment {
        start,
        bit_time,
        signal,
        level_before,
        hint,
        distorted,
        then_filler,
    } = seg;
    l.start = start;
    l.bit_time = bit_time;
    l.level_before = level_before;
    l.distorted = distorted;
    l.then_filler = then_filler;
    Some((
        std::mem::replace(&mut l.signal, signal),
        std::mem::replace(&mut l.hint, hint),
    ))
}

/// The inversion a carried copy is followed with, by the line's level at its start (index 0:
/// low, 1: high): a telegram from the other level than its `level_before` (410B §1 repeater;
/// spec-notes "Followed copies").
fn single_inv(seg: &LineSegment) -> [bool; 2] {
    let bits = matches!(seg.signal, LineSignal::Bits(_));
    [bits && seg.level_before, bits && !seg.level_before]
}

/// The inversions of a carried copy of `seg`'s bits starting at `start`, merged after the
/// carried copy `before` (410B §1 repeater): chained from the level `before` leaves at that
/// start (`Transmitter::skip_followed`; spec-notes "Merged carried copies").
#[inline(always)]
fn chained_inversion(before: &LineSegment, start: Instant, seg: &LineSegment) -> [bool; 2] {
    let bits = matches!(seg.signal, LineSignal::Bits(_));
    let level = before.level_at(start);
    let first = single_inv(before);
    [
        bits && seg.level_before != (level != first[0]),
        bits && seg.level_before != (level != first[1]),
    ]
}

/// Whether background `bg` resumed at `at` is plain filler of bit time `bit_time` (filler,
/// or the implied filler of a forwarded telegram that has ended by then), undistorted.
#[inline(always)]
fn resumes_filler(bg: &LineSegment, at: Instant, bit_time: Duration) -> bool {
    let filler = match &bg.signal {
        LineSignal::Filler => true,
        LineSignal::Bits(_) => bg.then_filler && bg.end().is_some_and(|e| e <= at),
        LineSignal::Dark | LineSignal::Light => false,
    };
    filler && !bg.distorted && bg.bit_time == bit_time
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use sercos_wire::line::BitVec;

    /// One bit time; every instant below is a whole number of them (ties are frequent).
    const BT: u64 = 1_000;

    /// `n` bits, every third one set from bit `first` on (a pattern with edges and runs).
    fn every_third(n: usize, first: usize) -> BitVec {
        let mut v = BitVec::new();
        for i in 0..n {
            v.push(i % 3 == first % 3);
        }
        v
    }

    /// What is done to the transmitter, at a time counted in bit times from the last release.
    #[derive(Debug, Clone)]
    enum Op {
        /// A carried copy (`push_forwarded` with carried forwarding): bits (with or without
        /// implied filler) or filler, from a level.
        Carried {
            off: u64,
            bits: Option<(Vec<bool>, bool)>,
            level: bool,
        },
        /// A background segment released as output (filler or dark).
        Background { off: u64, filler: bool },
        /// An own telegram.
        Own {
            off: u64,
            half: bool,
            len: u8,
            presync: bool,
        },
        /// A release this many bit times past the last one (and half a bit time more).
        Release(u64, bool),
    }

    fn op() -> impl Strategy<Value = Op> {
        prop_oneof![
            4 => (
                0u64..40,
                proptest::option::of((proptest::collection::vec(any::<bool>(), 0..120), any::<bool>())),
                any::<bool>()
            )
                .prop_map(|(off, bits, level)| Op::Carried { off, bits, level }),
            1 => (0u64..40, any::<bool>()).prop_map(|(off, filler)| Op::Background { off, filler }),
            2 => (0u64..40, any::<bool>(), 1u8..4, any::<bool>())
                .prop_map(|(off, half, len, presync)| Op::Own { off, half, len, presync }),
            3 => (0u64..80, any::<bool>()).prop_map(|(d, half)| Op::Release(d, half)),
        ]
    }

    /// [`Transmitter::sole_own`] from a walk of the background queue.
    fn sole_own_from_queues(tx: &Transmitter) -> Option<(Instant, Instant, Duration)> {
        let own = tx.own.front()?;
        (tx.own.is_single()
            && tx.released.is_empty()
            && tx.background.iter().all(|q| q.carried)
            && tx.resume_at.is_none_or(|r| tx.resume_is_silent(r)))
        .then(|| (own.start, own.end(), own.bit_time))
    }

    /// `write_over` leaves its slot as the assignment of the whole segment does, every field
    /// written (a bits segment with its hint over a filler, a distorted one over one that is
    /// not, either over nothing), and hands back the replaced segment's signal and hint.
    #[test]
    fn a_segment_written_over_another_is_as_assigned() {
        let bt = Duration::from_picos(BT);
        let at = |bits: u64| Instant::from_picos(bits * BT);
        let bits = every_third(12, 1);
        let hinted = LineSegment {
            hint: Some(Shared::new(FrameHint {
                telegram: Shared::from(&[1u8, 2][..]),
                offset: 4,
                coded: None,
            })),
            then_filler: true,
            ..LineSegment::bits(at(3), bt, bits.clone(), true)
        };
        let filler = LineSegment {
            distorted: true,
            ..LineSegment::steady(at(7), bt.saturating_mul(2), LineSignal::Filler, false)
        };
        let segments = [hinted, filler];
        for before in [None, Some(&segments[0]), Some(&segments[1])] {
            for seg in &segments {
                let mut slot = before.cloned();
                let parts = write_over(&mut slot, seg.clone());
                assert_eq!(format!("{slot:?}"), format!("{:?}", Some(seg)));
                assert_eq!(
                    format!("{parts:?}"),
                    format!("{:?}", before.map(|b| (b.signal.clone(), b.hint.clone())))
                );
            }
        }
    }

    /// The merge's inversion taken as the queued copy's own (`push_carried`'s `follows`) only
    /// when the queued copy is the copy of the segment `follows` names: with a copy of
    /// another segment queued, the chained inversion is kept (debug builds check it), and
    /// the merge ends as the general push's (410B §1 repeater; spec-notes "Merged carried
    /// copies").
    #[test]
    fn a_merge_after_another_copy_chains_its_inversion() {
        let bt = Duration::from_picos(BT);
        let at = |bits: u64| Instant::from_picos(bits * BT);
        let bits = every_third(20, 0);
        let first = LineSegment {
            then_filler: true,
            ..LineSegment::bits(at(10), bt, bits.clone(), false)
        };
        // The receiver's last segment (starting at 20) is not `first`; `seg` starts from
        // the level other than the one `first`'s copy leaves at its start.
        let seg_at = at(100);
        let level = !first.level_at(seg_at);
        for follows in [None, Some(at(20)), Some(at(10))] {
            let mut tx = Transmitter {
                carried_forwarding: true,
                ..Transmitter::default()
            };
            tx.push_carried(&first, 0, None);
            let seg = LineSegment {
                then_filler: true,
                ..LineSegment::bits(seg_at, bt, bits.clone(), level)
            };
            let mut general = tx.clone();
            general.push_forwarded(LineSegment {
                distorted: false,
                ..seg.without_hint()
            });
            if follows == Some(at(10)) {
                // `follows` names `first`: the level is the copy's (the caller's promise).
                let seg = LineSegment {
                    then_filler: true,
                    ..LineSegment::bits(seg_at, bt, bits.clone(), !level)
                };
                let mut general = tx.clone();
                general.push_forwarded(LineSegment {
                    distorted: false,
                    ..seg.without_hint()
                });
                tx.push_carried(&seg, 0, follows);
                assert_eq!(format!("{tx:?}"), format!("{general:?}"));
                continue;
            }
            tx.push_carried(&seg, 0, follows);
            assert!(tx.tail.is_some(), "the copy is merged");
            assert_eq!(
                format!("{tx:?}"),
                format!("{general:?}"),
                "follows {follows:?}"
            );
        }
    }

    /// A merged copy behind a resumed rest (a shadowed telegram resumed at its next bit
    /// boundary, queued before the merged entry): the rest is released, then the copies are
    /// followed, as with the queue of separate copies (spec-notes "Merged carried copies").
    #[test]
    fn a_resumed_rest_before_a_merged_copy_is_released() {
        let bt = Duration::from_picos(BT);
        let at = |bits: u64| Instant::from_picos(bits * BT);
        let mut tx = Transmitter {
            carried_forwarding: true,
            ..Transmitter::default()
        };
        let mut plain = tx.clone();
        let own_at = Instant::from_picos(21 * BT / 2);
        for t in [&mut tx, &mut plain] {
            t.transmit(own_at, bt, false, &[0x12, 0x34]);
            t.push_forwarded(LineSegment::bits(at(11), bt, every_third(200, 0), false));
            t.release_with::<true>(at(12));
            t.push_forwarded(LineSegment::bits(at(300), bt, every_third(20, 0), true));
            t.push_forwarded(LineSegment::bits(at(310), bt, every_third(20, 0), false));
        }
        plain.split_merged();
        assert!(tx.tail.is_some(), "the second copy is merged");
        let mut out = Vec::new();
        let mut plain_out = Vec::new();
        tx.release(at(400));
        tx.take_released(&mut out);
        plain.release_with::<false>(at(400));
        plain.take_released(&mut plain_out);
        assert!(!out.is_empty(), "the resumed rest is released");
        assert_eq!(out, plain_out);
        assert_eq!(format!("{plain:?}"), format!("{:?}", tx.separate()));
    }

    /// The merged follow and the own telegram after it are taken as one
    /// (`Transmitter::release_merged_then_own`) only when the loop's first two turns would
    /// be exactly those: not with a resume pending, nor with a resumed rest queued before
    /// the merged entry, nor with copies that start before the last own telegram's end
    /// (shadowed); and the loop goes on after it (a second own telegram queued). Each case
    /// against the loop of separate copies, state and output.
    #[test]
    fn a_merged_copy_then_own_is_taken_as_one_only_when_the_loop_would() {
        let bt = Duration::from_picos(BT);
        let at = |bits: u64| Instant::from_picos(bits * BT);
        let own_at = Instant::from_picos(21 * BT / 2);
        // The instant the own telegram ends (a release there queues the rest of the copy
        // it shadows, which resumes at its next bit boundary).
        const OWN_END: Instant = Instant::from_picos(0);
        // Each case: the releases before the copies are queued, where the copies start,
        // and the releases after; then an own telegram is queued after the copies and all
        // is released.
        let mut cases: Vec<(Vec<Instant>, u64, Vec<Instant>)> = vec![
            // A resume pending (the own telegram still being sent).
            (vec![at(12)], 300, vec![]),
            // A resumed rest queued before the merged entry.
            (vec![at(12)], 300, vec![OWN_END]),
            // The case the short path takes.
            (vec![at(12), at(200)], 300, vec![]),
        ];
        // Copies that start before the last own telegram's end (shadowed), its resume
        // taken: at a few offsets, so that the level they leave differs from the line's.
        for copies in 16..24 {
            cases.push((vec![at(12), at(200)], copies, vec![]));
        }
        for (case, (before, copies, after)) in cases.into_iter().enumerate() {
            for (implied, owns) in [(false, 1), (true, 1), (false, 2), (true, 2)] {
                let mut tx = Transmitter {
                    carried_forwarding: true,
                    implied_filler: implied,
                    ..Transmitter::default()
                };
                tx.push_background(LineSegment::steady(at(0), bt, LineSignal::Filler, false));
                tx.transmit(own_at, bt, false, &[0x12, 0x34]);
                tx.push_forwarded(LineSegment::bits(at(11), bt, every_third(200, 0), false));
                let release = |tx: &mut Transmitter, r: Instant| {
                    let r = if r == OWN_END { tx.own_until } else { r };
                    tx.release(r);
                    tx.take_released(&mut Vec::new());
                };
                for &r in &before {
                    release(&mut tx, r);
                }
                tx.push_forwarded(LineSegment::bits(at(copies), bt, every_third(20, 2), true));
                tx.push_forwarded(LineSegment {
                    then_filler: true,
                    ..LineSegment::bits(at(copies + 10), bt, every_third(20, 1), false)
                });
                assert!(tx.tail.is_some(), "case {case}: the second copy is merged");
                for &r in &after {
                    release(&mut tx, r);
                }
                tx.transmit(at(copies + 40), bt, false, &[0x56]);
                if owns == 2 {
                    // A second own telegram queued behind the first (then the release does
                    // not end with the first).
                    tx.transmit(at(copies + 40), bt, false, &[0x78]);
                }
                let mut plain = tx.separate();
                let (mut out, mut plain_out) = (Vec::new(), Vec::new());
                tx.release_with::<true>(at(copies + 400));
                tx.take_released(&mut out);
                plain.release_with::<false>(at(copies + 400));
                plain.take_released(&mut plain_out);
                assert_eq!(out, plain_out, "case {case}, implied {implied}, {owns} own");
                assert_eq!(
                    format!("{plain:?}"),
                    format!("{:?}", tx.separate()),
                    "case {case}, implied {implied}, {owns} own"
                );
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(512)))]

        /// The release's short paths leave exactly the state of the general loop's turns
        /// one by one, after every release (carried copies, background, own telegrams with
        /// and without implied filler, ties of every kind).
        #[test]
        fn short_paths_release_as_the_general_loop(
            ops in proptest::collection::vec(op(), 1..40),
            implied in any::<bool>(),
        ) {
            let mut tx = Transmitter {
                implied_filler: implied,
                carried_forwarding: true,
                ..Transmitter::default()
            };
            // The queue of separate copies: split after every push (never merged).
            let mut plain = tx.clone();
            let bt = Duration::from_picos(BT);
            let at = |now: u64, off: u64| Instant::from_picos((now + off) * BT);
            tx.push_background(LineSegment::steady(at(0, 0), bt, LineSignal::Filler, false));
            plain.push_background(LineSegment::steady(at(0, 0), bt, LineSignal::Filler, false));
            let mut now = 0u64;
            for op in ops {
                match op {
                    Op::Carried { off, bits, level } => {
                        let seg = match bits {
                            Some((bits, then_filler)) => {
                                let mut v = BitVec::new();
                                for b in bits {
                                    v.push(b);
                                }
                                LineSegment {
                                    then_filler,
                                    ..LineSegment::bits(at(now, off), bt, v, level)
                                }
                            }
                            None => LineSegment::steady(at(now, off), bt, LineSignal::Filler, level),
                        };
                        plain.push_forwarded(seg.clone());
                        plain.split_merged();
                        // Built in place (the repeater's latency left out).
                        tx.push_carried(&seg, 0, None);
                    }
                    Op::Background { off, filler } => {
                        let signal = if filler { LineSignal::Filler } else { LineSignal::Dark };
                        tx.push_background(LineSegment::steady(at(now, off), bt, signal.clone(), false));
                        plain.push_background(LineSegment::steady(at(now, off), bt, signal, false));
                    }
                    Op::Own { off, half, len, presync } => {
                        // Half a bit time off the grid: a shadowed telegram resumes at its
                        // next bit boundary.
                        let telegram: Vec<u8> = (0..len).map(|i| i.wrapping_mul(0x5B)).collect();
                        let start = at(now, off).saturating_add(Duration::from_picos(BT / 2 * u64::from(half)));
                        tx.transmit(start, bt, presync, &telegram);
                        plain.transmit(start, bt, presync, &telegram);
                    }
                    Op::Release(d, half) => {
                        now += d;
                        let until = at(now, 0).saturating_add(Duration::from_picos(BT / 2 * u64::from(half)));
                        let mut general = plain.clone();
                        general.release_with::<false>(until);
                        // The own-first release (a master's take) from the same state.
                        let mut first = tx.clone();
                        first.release_own_first(until);
                        prop_assert_eq!(format!("{general:?}"), format!("{:?}", first.separate()));
                        tx.release_with::<true>(until);
                        prop_assert_eq!(format!("{general:?}"), format!("{:?}", tx.separate()));
                        plain.release_with::<true>(until);
                        // Taken as a simulation takes them (then `sole_own` can answer).
                        tx.take_released(&mut Vec::new());
                        plain.take_released(&mut Vec::new());
                    }
                }
                // What is kept beside the queues matches them, and what is asked of the
                // queues between releases is what the queue of separate copies says.
                prop_assert_eq!(format!("{plain:?}"), format!("{:?}", tx.separate()));
                prop_assert_eq!(tx.next_release_at(), plain.next_release_at());
                prop_assert_eq!(tx.next_own_release_at(), plain.next_own_release_at());
                prop_assert_eq!(
                    tx.background_starts().collect::<Vec<_>>(),
                    plain.background_starts().collect::<Vec<_>>()
                );
                prop_assert_eq!(tx.sole_own(), plain.sole_own());
                prop_assert_eq!(tx.uncarried, tx.count_uncarried());
                prop_assert_eq!(tx.next_release, tx.compute_next_release());
                prop_assert_eq!(tx.sole_own(), sole_own_from_queues(&tx));
            }
        }
    }
}
