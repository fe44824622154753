#!/usr/bin/env bash
# Regenerates the pictures in docs/images from the real data in ../shared.
set -euo pipefail
cd "$(dirname "$0")/.."
gd=build/release/gazedirector
out=docs/images
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
data=../shared/data

# Landmarks and head pose on a portrait and on a group photo.
$gd landmarks $data/images/d30.jpg -o "$tmp/d30.json" --overlay "$tmp/d30.png" -q
$gd landmarks $data/dlib-faces/bald_guys.jpg -o "$tmp/group.json" --overlay "$tmp/group.png" -q
ffmpeg -v error -y -i "$tmp/d30.png" -vf "crop=400:400:100:130" "$out/landmarks_d30.jpg"
ffmpeg -v error -y -i "$tmp/group.png" -vf "scale=900:-2" -q:v 4 "$out/landmarks_group.jpg"

# The model at several gaze directions, the eyelids following (the paper's lid figure).
tiles=()
for pitch in 20 0 -20; do
  for yaw in 25 0 -25; do
    $gd render --gaze "$pitch,$yaw" --eyelid "$pitch" --size 400x200 -o "$tmp/model_${pitch}_${yaw}.png" -q
    tiles+=(-i "$tmp/model_${pitch}_${yaw}.png")
  done
done
ffmpeg -v error -y "${tiles[@]}" -filter_complex "xstack=inputs=9:layout=0_0|w0_0|w0+w1_0|0_h0|w0_h0|w0+w1_h0|0_h0+h1|w0_h0+h1|w0+w1_h0+h1" "$out/model_gaze_grid.png"

# The fitted model and gaze rays over a real face.
$gd track $data/images/d30.jpg -o "$tmp/d30_fit.json" --overlay "$tmp/d30_fit.png" -q
ffmpeg -v error -y -i "$tmp/d30_fit.png" -vf "crop=300:150:110:190,scale=600:-2" "$out/fit_d30.jpg"

# Eye contact on real faces: before | after.
for name in d30 d19 s12; do
  $gd redirect $data/images/$name.jpg -o "$tmp/${name}_contact.png" --look-at camera --side-by-side -q
done
ffmpeg -v error -y -i "$tmp/d30_contact.png" -vf "crop=1200:260:0:170,scale=900:-2" "$out/eye_contact_d30.jpg"
ffmpeg -v error -y -i "$tmp/d19_contact.png" -vf "scale=900:-2" -q:v 3 "$out/eye_contact_d19.jpg"
ffmpeg -v error -y -i "$tmp/s12_contact.png" -vf "scale=900:-2" -q:v 3 "$out/eye_contact_s12.jpg"

# Converging eyes (s42.jpg): the photo, the fit with the vergence free and eye contact.
$gd track $data/images/s42.jpg -o "$tmp/s42_fit.json" --overlay "$tmp/s42_fit.png" -q
$gd redirect $data/images/s42.jpg --fits "$tmp/s42_fit.json" -o "$tmp/s42_contact.png" --look-at camera -q
ffmpeg -v error -y -i $data/images/s42.jpg -i "$tmp/s42_fit.png" -i "$tmp/s42_contact.png" -filter_complex \
  "[0]crop=220:70:150:223[a];[1]crop=220:70:150:223[b];[2]crop=220:70:150:223[c];[a][b][c]hstack=inputs=3,scale=1320:-2" \
  "$out/converging_s42.jpg"

# Large angles: one face over pitch -15..15 and yaw -45..45 degrees (head frame).
tiles=()
for pitch in 15 0 -15; do
  for yaw in 45 30 15 0 -15 -30 -45; do
    $gd redirect $data/images/d30.jpg --fits "$tmp/d30_fit.json" -o "$tmp/grid_${pitch}_${yaw}.png" \
      --gaze "$pitch,$yaw" --frame head -q
    ffmpeg -v error -y -i "$tmp/grid_${pitch}_${yaw}.png" -vf "crop=200:80:140:212" "$tmp/grid_${pitch}_${yaw}_crop.png"
    tiles+=(-i "$tmp/grid_${pitch}_${yaw}_crop.png")
  done
done
layout=""
for row in 0 1 2; do
  for col in 0 1 2 3 4 5 6; do layout+="$((col * 200))_$((row * 80))|"; done
done
ffmpeg -v error -y "${tiles[@]}" -filter_complex "xstack=inputs=21:layout=${layout%|},scale=1400:-2" "$out/large_angles_d30.jpg"

# Video: d3.mp4 redirected to the camera, and a scripted behaviour, beside the original.
cat > "$tmp/script.json" <<'JSON'
{"transition_s": 0.3,
 "segments": [{"start_s": 0, "target": "camera"},
              {"start_s": 3, "target": {"look_at": [-400, 0, 100]}},
              {"start_s": 5, "reading": {"width_deg": 24, "line_s": 1.2, "lines": 4, "line_spacing_deg": 3, "pitch_deg": -8}}]}
JSON
cp "$tmp/script.json" docs/gaze_script_example.json
$gd redirect $data/video/d3.mp4 -o "$tmp/d3_camera.mp4" --look-at camera --side-by-side -q
$gd redirect $data/video/d3.mp4 --fits "$tmp/d3_camera.mp4.fits.jsonl" -o "$tmp/d3_script.mp4" --script "$tmp/script.json" --side-by-side -q
ffmpeg -v error -y -i "$tmp/d3_camera.mp4" -t 3 -vf "crop=1024:220:0:130,fps=8,scale=480:-2:flags=lanczos,split[a][b];[a]palettegen[p];[b][p]paletteuse" "$out/d3_eye_contact.gif"
# Her looks down at frames 70, 90 and 125 turned to the camera: the lids lift with the eyes.
ffmpeg -v error -y -i "$tmp/d3_camera.mp4" -vf "select=eq(n\\,70)+eq(n\\,90)+eq(n\\,125),crop=1024:120:0:230,tile=1x3" \
  -frames:v 1 -q:v 3 "$out/d3_eye_contact_looking_down.jpg"
ffmpeg -v error -y -ss 4.5 -i "$tmp/d3_script.mp4" -t 5 -vf "crop=1024:220:0:130,fps=8,scale=480:-2:flags=lanczos,split[a][b];[a]palettegen[p];[b][p]paletteuse" "$out/d3_reading.gif"

# The known failure: d10.mp4 turned to the camera, frames 200, 300, 400 (original left).
$gd redirect $data/video/d10.mp4 -o "$tmp/d10_camera.mp4" --look-at camera -q
rows=()
for spec in 200:195 300:175 400:185; do  # frame:top of the eye band
  frame=${spec%:*} top=${spec#*:}
  for video in $data/video/d10.mp4 "$tmp/d10_camera.mp4"; do
    ffmpeg -v error -y -i "$video" -vf "select=eq(n\\,$frame),crop=240:90:128:$top,scale=480:180" -frames:v 1 "$tmp/d10_${frame}_$(basename "$video" .mp4).png"
  done
  ffmpeg -v error -y -i "$tmp/d10_${frame}_d10.png" -i "$tmp/d10_${frame}_d10_camera.png" -filter_complex hstack "$tmp/d10_row_$frame.png"
  rows+=(-i "$tmp/d10_row_$frame.png")
done
ffmpeg -v error -y "${rows[@]}" -filter_complex vstack=3 "$out/known_failure_d10.png"

# The targets the Hsu et al. (2019) peer's pictures show (../shared/peers/hsu2019/verify), on the same
# stills' eye bands, so that the two can be held side by side: offsets from the fitted gaze (up, and
# toward the image's left or right), then eye contact.
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
for name_crop in d19:354:104:191:283 d30:199:58:139:237 s42:245:72:136:223; do
  name=${name_crop%%:*} crop=${name_crop#*:}
  cells=()
  for spec in input: "0,0:as fitted" "10,0:up 10" "-10,0:down 10" "0,-10:left 10" "0,10:right 10" "20,0:up 20" camera:camera; do
    offset=${spec%%:*} label=${spec#*:}
    src=$data/images/$name.jpg
    if [ "$offset" = camera ]; then
      src="$tmp/peer_${name}_camera.png"
      $gd redirect $data/images/$name.jpg -o "$src" --look-at camera -q
    elif [ "$offset" != input ]; then
      src="$tmp/peer_${name}_$offset.png"
      $gd redirect $data/images/$name.jpg -o "$src" --offset="$offset" -q
    fi
    [ "$offset" = input ] && label=input
    text=""
    [ -f "$font" ] && text=",drawtext=fontfile=$font:text='$name $label':x=6:y=6:fontsize=18:fontcolor=yellow"
    ffmpeg -v error -y -i "$src" -vf "crop=$crop,scale=408:120:flags=lanczos$text" "$tmp/peer_${name}_${#cells[@]}.png"
    cells+=("$tmp/peer_${name}_${#cells[@]}.png")
  done
  ffmpeg -v error -y -i "${cells[0]}" -i "${cells[1]}" -i "${cells[2]}" -i "${cells[3]}" -filter_complex hstack=4 "$tmp/peer_a_$name.png"
  ffmpeg -v error -y -i "${cells[4]}" -i "${cells[5]}" -i "${cells[6]}" -i "${cells[7]}" -filter_complex hstack=4 "$tmp/peer_b_$name.png"
done
for part in a b; do
  ffmpeg -v error -y -i "$tmp/peer_${part}_d19.png" -i "$tmp/peer_${part}_d30.png" -i "$tmp/peer_${part}_s42.png" \
    -filter_complex vstack=3 -q:v 3 "$out/peer_targets_$part.jpg"
done

# Evaluation figures.
$gd eval redirect-columbia --plot "$out/eval_redirect_columbia.png" -q > "$tmp/redirect_columbia.txt"
# The paper's protocol (head pose 0, no glasses), as the README's accuracy table; about 3 minutes.
$gd eval columbia --poses 0 --exclude-subjects 0001 0008 0010 0011 0012 0016 0017 0022 0023 \
  --plot "$out/eval_columbia.png" -q > "$tmp/columbia.txt"
echo "figures written to $out"
