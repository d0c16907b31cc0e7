//! The device end of the coil protocol: acknowledgements, device limits and the watchdog.

use std::time::Duration;

use crate::protocol::{
    AckStatus, Decoded, Message, PROTOCOL_VERSION, WATCHDOG_MAX_MS, WATCHDOG_MIN_MS, ack_flags,
};

/// What handling one frame did, for the log.
#[derive(Debug, Clone, PartialEq)]
pub enum DeviceEvent {
    /// A session opened (HELLO accepted).
    Hello {
        /// The watchdog timeout now in force (ms).
        watchdog_ms: u32,
    },
    /// New currents applied.
    Currents,
    /// A repeated SET_CURRENTS (same sequence number): applied again.
    Duplicate,
    /// A heartbeat.
    Heartbeat,
    /// Currents zeroed on request.
    Zero,
    /// A message refused with this status (currents zeroed when over the limit).
    Refused(AckStatus),
    /// A frame that failed its checksum (NAK sent).
    BadFrame,
}

/// The state of the emulated coil driver.
#[derive(Debug, Clone)]
pub struct DeviceState {
    currents: Vec<f64>,
    limits: Vec<f64>,
    watchdog: Duration,
    /// Clock time of the last valid frame.
    last_rx: Option<Duration>,
    tripped: bool,
    last_seq: Option<u16>,
}

impl DeviceState {
    /// A device with `limits.len()` channels, refusing currents beyond `limits` (A). Times
    /// given to it are its clock's (the emulator's [`crate::clock::Clock`]).
    pub fn new(limits: Vec<f64>, watchdog: Duration) -> Self {
        Self {
            currents: vec![0.0; limits.len()],
            limits,
            watchdog,
            last_rx: None,
            tripped: false,
            last_seq: None,
        }
    }

    /// The currents in force (A).
    pub fn currents(&self) -> &[f64] {
        &self.currents
    }

    /// The watchdog timeout in force.
    pub fn watchdog(&self) -> Duration {
        self.watchdog
    }

    /// When (clock time) the last valid frame arrived.
    pub fn last_rx(&self) -> Option<Duration> {
        self.last_rx
    }

    /// True when every current is zero.
    pub fn is_zero(&self) -> bool {
        self.currents.iter().all(|c| *c == 0.0)
    }

    /// Zeroes the currents (a disconnect or a fault); true if they were not zero.
    pub fn zero(&mut self) -> bool {
        let was = !self.is_zero();
        self.currents.iter_mut().for_each(|c| *c = 0.0);
        was
    }

    /// Zeroes the currents when nothing valid arrived for the watchdog time; true when it
    /// tripped now (currents were non-zero).
    pub fn check_watchdog(&mut self, now: Duration) -> bool {
        match self.last_rx {
            Some(t) if now.saturating_sub(t) > self.watchdog && !self.is_zero() => {
                self.zero();
                self.tripped = true;
                true
            }
            _ => false,
        }
    }

    /// Handles one decoded frame: the reply to send and what happened.
    pub fn handle(&mut self, d: Decoded, now: Duration) -> (Message, DeviceEvent) {
        let (seq, result) = match d {
            Decoded::BadChecksum => return (Message::Nak, DeviceEvent::BadFrame),
            Decoded::Invalid { seq, status, .. } => (seq, Err(status)),
            Decoded::Message { seq, msg } => (seq, Ok(msg)),
        };
        self.last_rx = Some(now);
        let event = match result {
            Err(status) => DeviceEvent::Refused(status),
            Ok(Message::Hello {
                version,
                channels,
                watchdog_ms,
            }) => {
                if version != PROTOCOL_VERSION {
                    DeviceEvent::Refused(AckStatus::BadVersion)
                } else if channels as usize != self.currents.len() {
                    DeviceEvent::Refused(AckStatus::ChannelMismatch)
                } else {
                    self.watchdog = Duration::from_millis(
                        watchdog_ms.clamp(WATCHDOG_MIN_MS, WATCHDOG_MAX_MS) as u64,
                    );
                    DeviceEvent::Hello {
                        watchdog_ms: self.watchdog.as_millis() as u32,
                    }
                }
            }
            Ok(Message::SetCurrents(c)) => {
                if c.len() != self.currents.len() {
                    DeviceEvent::Refused(AckStatus::ChannelMismatch)
                } else if c
                    .iter()
                    .zip(&self.limits)
                    .any(|(x, l)| (*x as f64).abs() > *l)
                {
                    self.zero();
                    DeviceEvent::Refused(AckStatus::OverLimit)
                } else {
                    let dup = self.last_seq == Some(seq);
                    self.currents = c.iter().map(|x| *x as f64).collect();
                    if dup {
                        DeviceEvent::Duplicate
                    } else {
                        DeviceEvent::Currents
                    }
                }
            }
            Ok(Message::Heartbeat) => DeviceEvent::Heartbeat,
            Ok(Message::Zero) => {
                self.zero();
                DeviceEvent::Zero
            }
            Ok(_) => DeviceEvent::Refused(AckStatus::UnknownType),
        };
        self.last_seq = Some(seq);
        let status = match &event {
            DeviceEvent::Refused(s) => *s,
            _ => AckStatus::Ok,
        };
        let mut flags = 0;
        if std::mem::take(&mut self.tripped) {
            flags |= ack_flags::WATCHDOG_TRIPPED;
        }
        if self.is_zero() {
            flags |= ack_flags::CURRENTS_ZERO;
        }
        let device_ms = now.as_millis() as u32;
        (
            Message::Ack {
                seq,
                status,
                flags,
                device_ms,
            },
            event,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn watchdog_zeroes_after_silence_and_reports_it() {
        let t0 = Duration::from_secs(7);
        let mut d = DeviceState::new(vec![8.0; 5], Duration::from_millis(200));
        let (ack, ev) = d.handle(
            Decoded::Message {
                seq: 1,
                msg: Message::SetCurrents(vec![1.0; 5]),
            },
            t0,
        );
        assert_eq!(ev, DeviceEvent::Currents);
        assert!(matches!(
            ack,
            Message::Ack {
                seq: 1,
                status: AckStatus::Ok,
                flags: 0,
                ..
            }
        ));
        assert!(!d.check_watchdog(t0 + Duration::from_millis(150)));
        assert!(d.check_watchdog(t0 + Duration::from_millis(201)));
        assert!(d.is_zero());
        let (ack, _) = d.handle(
            Decoded::Message {
                seq: 2,
                msg: Message::Heartbeat,
            },
            t0 + Duration::from_millis(250),
        );
        assert!(
            matches!(ack, Message::Ack { flags, .. } if flags & ack_flags::WATCHDOG_TRIPPED != 0)
        );
    }

    #[test]
    fn over_limit_is_refused_and_zeroes() {
        let t0 = Duration::from_secs(7);
        let mut d = DeviceState::new(vec![8.0; 2], Duration::from_millis(200));
        d.handle(
            Decoded::Message {
                seq: 1,
                msg: Message::SetCurrents(vec![1.0, 1.0]),
            },
            t0,
        );
        let (ack, ev) = d.handle(
            Decoded::Message {
                seq: 2,
                msg: Message::SetCurrents(vec![9.0, 1.0]),
            },
            t0,
        );
        assert_eq!(ev, DeviceEvent::Refused(AckStatus::OverLimit));
        assert!(
            matches!(
                ack,
                Message::Ack {
                    status: AckStatus::OverLimit,
                    ..
                }
            ) && d.is_zero()
        );
        let (ack, _) = d.handle(Decoded::BadChecksum, t0);
        assert_eq!(ack, Message::Nak);
    }
}
