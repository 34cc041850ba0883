<?xml version="1.0" encoding="UTF-8"?>
<tileset version="1.10" name="tiles" tilewidth="4" tileheight="4" spacing="1" margin="1" tilecount="4" columns="2">
 <image source="tiles.png" width="12" height="12"/>
</tileset>
