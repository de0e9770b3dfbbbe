/// \file
/// \brief Playback's sound on the main thread: the audio player of a session (attachAudio), the
/// volume and mute commands, the sound's counters. See playback.h and audio_player.h.

#include <algorithm>
#include <cmath>
#include <string>

#include "depthtouch/hal/audio_source.h"
#include "depthtouch/platform/report_file.h"

#include "playback_impl.h"

namespace depthtouch::playback {

/// \return \a before's counters with \a later's added (a later session's queue and end win).
AudioStats addedAudioStats(AudioStats before, const AudioStats &later)
{
    before.framesWritten += later.framesWritten;
    before.silenceFrames += later.silenceFrames;
    before.underruns += later.underruns;
    before.delaySeconds = later.delaySeconds;
    before.ended = later.ended;
    if (before.lost.empty())
        before.lost = later.lost;
    return before;
}

void attachAudio(Playback::Impl &m, Session &s, PlaybackInfo &info)
{
    if (!m.config.audioEnabled || m.hal.audioOutput == nullptr || !m.hal.makeAudioSource)
        return;
    if (s.receiver->source().info().audio.empty())
        return;
    Result<std::unique_ptr<hal::AudioSource>> source{nullptr};
    std::shared_ptr<hal::AudioPacketSink> sink;
    if (s.live) { // one demuxer: it hands the sound's packets over (no second reader)
        if (!m.hal.makeLiveAudioSource)
            return;
        const hal::AudioStreamInfo &stream = s.receiver->source().info().audio.front();
        auto live = m.hal.makeLiveAudioSource(stream);
        if (live) {
            sink = live->sink;
            source = std::move(live->source);
        } else {
            source = unexpected(live.error());
        }
        if (source && *source && sink) {
            if (auto d = s.receiver->source().deliverAudio(stream.containerIndex); !d)
                source = unexpected(d.error());
        }
    } else {
        source = m.hal.makeAudioSource(m.openingUrl);
    }
    if (!source || !*source) {
        std::string why = source ? "no audio stream could be read" : source.error().what;
        const int rate = s.receiver->source().info().audio.front().sampleRate;
        if (rate < hal::kMinSourceRate || rate > hal::kMaxSourceRate) // a lying header
            why += " (the stream says " + std::to_string(rate) + " Hz)";
        info.notes.emplace_back("no sound: " + why);
        return;
    }
    AudioPlayerConfig ac = m.config.audio;
    ac.volume = m.volume;
    ac.mute = m.mute;
    auto player = AudioPlayer::create(**source, *m.hal.audioOutput, m.clock, ac);
    if (!player) {
        info.notes.emplace_back(std::string("no sound: the audio output refused it: ") +
                                player.error().what);
        return;
    }
    if (auto t = (*player)->startThread(); !t) {
        info.notes.emplace_back(std::string("no sound: ") + t.error().what);
        return;
    }
    if (sink)
        s.receiver->setAudioSink(sink); // before the decode thread starts
    const hal::AudioFormat f = (*source)->format();
    info.audio = std::to_string(f.sampleRate) + " Hz " + std::to_string(f.channels) + " ch";
    s.audioSource = std::move(*source);
    s.audio = std::move(*player);
}

std::string writeAvLog(const Playback::Impl &m)
{
    platform::ReportFile f(m.config.avLogPath);
    f.print("time_s,pts_s,offset_ms\n");
    const RenderShared::AvOffsets av = m.avOffsets();
    for (std::size_t i = 0; i < av.ms.size(); ++i)
        f.print("%.6f,%.6f,%.3f\n", av.at[i], av.pts[i], av.ms[i]);
    return f.close() ? std::string() : "cannot write the A/V log (disk full or no such folder?)";
}

Result<void> Playback::setVolume(double percent)
{
    Impl &m = *impl_;
    m.volume = options::kVolume.clamp(std::isfinite(percent) ? percent : 0.0); // a safety net
    m.osdEvents.fetch_add(1, std::memory_order_relaxed);
    if (m.owned && m.owned->audio)
        m.owned->audio->setVolume(m.volume);
    return ok();
}

Result<void> Playback::setMute(bool mute)
{
    Impl &m = *impl_;
    m.mute = mute;
    m.osdEvents.fetch_add(1, std::memory_order_relaxed);
    if (m.owned && m.owned->audio)
        m.owned->audio->setMute(mute);
    return ok();
}

} // namespace depthtouch::playback
