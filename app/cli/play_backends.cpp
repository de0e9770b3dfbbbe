/// \file
/// \brief A player's outputs, backends and pipeline as `play` opens them: see play_backends.h.

#include "play_backends.h"

#include <utility>
#include <vector>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/video_decoder.h"
#include "depthtouch/media/audio_reader.h"
#include "depthtouch/player/command.h"
#include "play_options.h"

namespace depthtouch::cli {

namespace {

/// \return \a cfg with the backend options \a options.
hal::BackendConfig withOptions(const hal::BackendConfig &cfg, const std::string &options)
{
    hal::BackendConfig c = cfg;
    c.options = hal::OptionList(options);
    return c;
}

/// Moves the backend \a made into \a into. \return nullopt, or the failure of \a part with
/// \a report's line: bad input for a name or option at fault (or with \a alwaysBadInput).
template <class T>
std::optional<PlayOpenFailure> take(Result<std::unique_ptr<T>> made, PlayPart part,
                                    const hal::SelectionReport &report, std::unique_ptr<T> &into,
                                    bool alwaysBadInput = false)
{
    if (!made)
        return PlayOpenFailure{part, report.message,
                               alwaysBadInput || made.error().code == Errc::InvalidArgument,
                               made.error()};
    into = std::move(*made);
    return std::nullopt;
}

/// Opens the display, the haptic device, the remote and the sound output of \a opt into \a b,
/// telling \a opened of each; checks the decoder and (with \a checkSource) the source names (one
/// clear line now; they are made per open). \return nullopt, or the first failure.
std::optional<PlayOpenFailure> openBackends(const PlayOptions &opt, const hal::BackendConfig &cfg,
                                            PlayBackends &b, const OnBackendOpened &opened,
                                            bool checkSource)
{
    const auto tell = [&opened](drivers::BackendKind kind, std::string_view names,
                                const hal::SelectionReport &report, bool awaiting) {
        if (opened)
            opened(OpenedBackend{kind, names, report, awaiting});
    };
    // A display the caller made is kept (libdepthtouch's render API: the host's framebuffer).
    if (!b.display) {
        if (auto bad =
                take(drivers::createDisplay(opt.display, withOptions(cfg, opt.displayOptions),
                                            &b.displayReport),
                     PlayPart::Display, b.displayReport, b.display))
            return bad;
        tell(drivers::BackendKind::Display, opt.display, b.displayReport, false);
    }
    // A player that stays up (--idle: the box's service) takes its haptic device and remote
    // when they are plugged in, after its start too (hot-plug).
    hal::BackendConfig hapticCfg = withOptions(cfg, opt.hapticOptions);
    hapticCfg.awaitDevice = opt.idle;
    if (auto bad = take(drivers::createHapticDevice(opt.haptic, hapticCfg, &b.hapticReport),
                        PlayPart::HapticDevice, b.hapticReport, b.device))
        return bad;
    tell(drivers::BackendKind::HapticDevice, opt.haptic, b.hapticReport,
         b.device->awaitingDevice());
    hal::SelectionReport rep;
    if (!opt.remote.empty() && opt.remote != "none") {
        hal::BackendConfig remoteCfg = withOptions(cfg, opt.remoteOptions);
        remoteCfg.awaitDevice = opt.idle;
        if (auto bad = take(drivers::createRemoteInput(opt.remote, remoteCfg, &rep),
                            PlayPart::RemoteInput, rep, b.remote))
            return bad;
        tell(drivers::BackendKind::RemoteInput, opt.remote, rep, b.remote->awaitingDevice());
        if (rep.chosen == "none") // a list that fell back to none (tty,none off a terminal)
            b.remote.reset();     // is no remote, as --remote none: remote-connected unavailable
    }
    if (!opt.noAudio && opt.audioDevice != "none") {
        const hal::BackendConfig audioCfg = withOptions(cfg, opt.audioDeviceOptions);
        if (auto bad = take(drivers::createAudioOutput(opt.audioDevice, audioCfg, &b.audioReport),
                            PlayPart::AudioOutput, b.audioReport, b.audio))
            return bad;
        tell(drivers::BackendKind::AudioOutput, opt.audioDevice, b.audioReport, false);
    }
    std::unique_ptr<hal::VideoDecoder> decoder;
    if (auto bad = take(
            drivers::createVideoDecoder(opt.decoder, withOptions(cfg, opt.decoderOptions), &rep),
            PlayPart::VideoDecoder, rep, decoder, true))
        return bad;
    if (!checkSource)
        return std::nullopt;
    std::unique_ptr<hal::MediaSource> source;
    return take(drivers::createMediaSource(opt.source, withOptions(cfg, opt.sourceOptions), &rep),
                PlayPart::MediaSource, rep, source, true);
}

/// \return the HAL of the player: \a b's display, device (none with `none`) and sound output, a
/// source and decoders per open, the sound of an input (media::AudioReader).
playback::PlaybackHal playbackHal(const PlayOptions &opt, const hal::BackendConfig &cfg,
                                  const PlayBackends &b)
{
    playback::PlaybackHal ph;
    ph.makeSource = [name = opt.source, c = withOptions(cfg, opt.sourceOptions)]() {
        return drivers::createMediaSource(name, c);
    };
    ph.makeDecoder = [name = opt.decoder, c = withOptions(cfg, opt.decoderOptions)](
                         const hal::StreamInfo &) { return drivers::createVideoDecoder(name, c); };
    ph.display = b.display.get();
    ph.device = b.noDevice() ? nullptr : b.device.get();
    ph.clock = cfg.clock;
    ph.audioOutput = b.audio.get();
    ph.makeAudioSource = [](const std::string &url) -> Result<std::unique_ptr<hal::AudioSource>> {
        auto reader = media::AudioReader::open(url);
        if (!reader)
            return unexpected(reader.error());
        return std::unique_ptr<hal::AudioSource>(std::move(*reader));
    };
    ph.makeLiveAudioSource =
        [](const hal::AudioStreamInfo &stream) -> Result<playback::PlaybackHal::LiveAudio> {
        auto reader = media::AudioReader::fromPackets(stream);
        if (!reader)
            return unexpected(reader.error());
        playback::PlaybackHal::LiveAudio live;
        live.sink = (*reader)->packetSink();
        live.source = std::move(*reader);
        return live;
    };
    return ph;
}

} // namespace

platform::OutputPathCheck checkPlayOutputs(const PlayOptions &opt, bool distinctFromInputs)
{
    // A missing folder is bad input, an output that takes no byte is lost at once. The sound
    // output's file (`wav`'s path=) is one of the outputs.
    const std::string wav =
        opt.noAudio ? std::string()
                    : drivers::audioOutputFilePath(opt.audioDevice, opt.audioDeviceOptions);
    std::vector<platform::OutputPathCheck> checks{
        platform::checkOutputPath("--record", opt.record),
        platform::checkOutputPath("--force-log", opt.forceLog),
        platform::checkOutputPath("--av-log", opt.avLog),
        platform::checkOutputPath("--stats", opt.stats, true),
        platform::checkOutputPath(kWavOutputOption, wav, true),
        platform::checkOutputFolder("--snapshot-dir", opt.snapshotDir)};
    // An output never replaces an input or another output (compared by file identity).
    if (distinctFromInputs)
        checks.push_back(platform::checkDistinctPaths(
            {{"the input", opt.url}, {"--config", opt.config}}, {{"--record", opt.record},
                                                                 {"--force-log", opt.forceLog},
                                                                 {"--av-log", opt.avLog},
                                                                 {"--stats", opt.stats},
                                                                 {kWavOutputOption, wav}}));
    for (platform::OutputPathCheck &c : checks)
        if (c.exitCode != platform::kOutputUsable)
            return std::move(c);
    return {};
}

std::optional<PlayOpenFailure> openPlayer(const PlayOptions &opt, platform::Clock &clock,
                                          OpenedPlayer &out, const OnBackendOpened &opened,
                                          const PlayerFeed *feed)
{
    hal::BackendConfig cfg;
    cfg.clock = &clock;
    if (auto bad = openBackends(opt, cfg, out.backends, opened, feed == nullptr))
        return bad;
    playback::PlaybackConfig config = landPlayOptions(opt);
    playback::PlaybackHal ph = playbackHal(opt, cfg, out.backends);
    if (feed != nullptr) {
        ph.makeSource = feed->makeSource;
        ph.masterClock = feed->masterClock;
        config.liveSilenceSeconds = 0.0;
    }
    auto pb = playback::Playback::create(config, std::move(ph));
    if (!pb)
        return PlayOpenFailure{PlayPart::Playback, pb.error().what,
                               pb.error().code == Errc::InvalidArgument, pb.error()};
    out.playback = std::move(*pb);
    return std::nullopt;
}

player::PlayerSettings playerSettings(const PlayOptions &opt)
{
    player::PlayerSettings settings;
    settings.url = opt.url;
    settings.loop = opt.loop;
    // A player that stays up (--idle: the box's service) waits for the next sender of a live
    // address that fell silent; one that ends at the end of its input ends there too.
    settings.reopenWhenSilent = opt.idle;
    settings.stereoMode = *player::stereoModeFromName(opt.stereo);
    settings.haptics = true;
    settings.stiffness = opt.stiffness;
    settings.volume = opt.volume;
    settings.mute = opt.mute;
    return settings;
}

} // namespace depthtouch::cli
